#!/usr/bin/env python3
"""Writes assets/rnet/joystick_synthetic.log: a SYNTHETIC candump log (`candump -l` format) of an
R-Net bus as pwsim reads it (hardware/rnet_joystick.h). It is not a recording of a real chair:
it follows the joystick layout published by the can2RNET project (0x02000M00#XxYy, X/Y signed
percent, every 10 ms) and adds some other periodic R-Net traffic, three garbage frames on the
joystick identifier, one frame of a second joystick slot, and a 300 ms loss of joystick frames.

Script (joystick slot 0, t in seconds from the first record):
  0.00-1.00  centred
  1.00-2.00  forward ramp 0 -> 60 %
  2.00-3.00  60 % forward, 30 % right
  3.00-3.30  no joystick frames (cable pulled): the reader's watchdog zeroes the deflection
  3.30-4.00  centred again
Usage: scripts/make-rnet-log.py [OUT]   (default assets/rnet/joystick_synthetic.log)
"""
import sys

T0_US = 1_700_000_000_000_000


def joystick(x, y, slot=0):
    return "%08X#%02X%02X" % (0x02000000 | (slot << 8), x & 0xFF, y & 0xFF)


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "assets/rnet/joystick_synthetic.log"
    records = []  # (time_us, frame text)
    for k in range(400):  # 10 ms joystick period, 4 s
        t_ms = 10 * k
        if 3000 <= t_ms < 3300:
            continue
        if t_ms < 1000:
            x, y = 0, 0
        elif t_ms < 2000:
            x, y = 0, round(60 * (t_ms - 1000) / 1000)
        elif t_ms < 3000:
            x, y = 30, 60
        else:
            x, y = 0, 0
        records.append((t_ms * 1000 + 250, joystick(x, y)))
    for k in range(40):  # JSM heartbeat, 100 ms
        records.append((k * 100_000 + 5_000, "03C30F0F#8787878787878787"))
    for k in range(4):  # battery level from the power module, 1 s
        records.append((k * 1_000_000 + 7_000, "1C0C0000#64"))
    records += [
        (1_500_600, "02000000#3C00FF"),  # three data bytes: garbage
        (1_600_600, "02000000#7F00"),    # X = 127 %, out of range: garbage
        (1_700_600, "02000000#R"),       # remote frame on the joystick id: garbage
        (2_500_600, joystick(-100, 0, slot=1)),  # a second joystick module: ignored
    ]
    records.sort()
    with open(out, "w") as f:
        for t_us, text in records:
            t = T0_US + t_us
            f.write("(%d.%06d) can0 %s\n" % (t // 1_000_000, t % 1_000_000, text))


if __name__ == "__main__":
    main()
