#!/usr/bin/env python3
"""Kills the first task that reads a FIFO, then feeds the FIFO to the next one.

usage: kill_fifo_reader.py FIFO CONTENT_FILE

The sweep's task reads its scene from FIFO, so it blocks in open() until a writer comes:
  1. open FIFO for writing: returns once the first attempt has opened it (it is mid-run,
     blocked on its input); find that process by its open file (/proc/PID/fd) and SIGKILL it;
  2. wait for it to be gone (pidfd), so the next open cannot meet the dying reader;
  3. open FIFO again: returns once the resubmitted attempt has opened it; write CONTENT_FILE.
Every wait is a blocking open (an event), bounded by an alarm. Prints the killed PID.
"""
import os
import select
import signal
import sys
import time

fifo, content_file = os.path.realpath(sys.argv[1]), sys.argv[2]
signal.alarm(120)  # the whole exchange; the test fails rather than hang


def readers():
    found = []
    for pid in os.listdir("/proc"):
        if not pid.isdigit() or int(pid) == os.getpid():
            continue
        try:
            for fd in os.listdir(f"/proc/{pid}/fd"):
                if os.readlink(f"/proc/{pid}/fd/{fd}") == fifo:
                    found.append(int(pid))
                    break
        except OSError:
            continue
    return found


writer = open(fifo, "w")  # blocks until attempt 1 opens the FIFO for reading
victims = readers()
for _ in range(2000):  # the reader's fd can appear a moment after the rendezvous: poll /proc
    if victims:
        break
    time.sleep(0.005)
    victims = readers()
if len(victims) != 1:
    sys.exit(f"kill_fifo_reader: expected one reader of {fifo}, found {victims}")
victim = os.pidfd_open(victims[0])
os.kill(victims[0], signal.SIGKILL)
select.select([victim], [], [])  # readable once the victim has exited (its fds are closed)
os.close(victim)
try:
    writer.close()
except BrokenPipeError:
    pass
print(victims[0], flush=True)

with open(content_file) as source:
    content = source.read()
with open(fifo, "w") as writer:  # blocks until the resubmitted attempt opens it
    writer.write(content)
