# One platform's drawing for docs/platforms.md (scripts/platform-drawings.sh sets geo, slice, name,
# words, commit, roll_box, pitch_box, heave_box, tmp). Left: the actuators in the base frame B at
# neutral and at a shown pose; right (platforms whose legs roll and pitch the plate): the
# (roll, pitch) workspace slice at heave 0 shaded by the largest stroke use, the end-of-stroke
# boundary at heave 0 and at ± half the heave box, and the axis box.
has_slice = (roll_box > 0)
set terminal pngcairo size (has_slice ? 1500 : 800),700 font ",10"
if (has_slice) {
  set table tmp."_c0.dat"; set contour base; set cntrparam levels discrete 1.0; unset surface
  splot slice index 0 using 1:2:4 with lines
  unset table
  set table tmp."_c1.dat"; splot slice index 1 using 1:2:4 with lines; unset table
  set table tmp."_c2.dat"; splot slice index 2 using 1:2:4 with lines; unset table
  unset contour; set surface
  set multiplot layout 1,2 title sprintf("%s (pwsim commit %s)", name, commit) font ",12"
} else {
  set multiplot layout 1,1 title sprintf("%s (pwsim commit %s)", name, commit) font ",12"
}
set title "grey: neutral; colour: ".words
set xlabel "x, forward [m]"; set ylabel "y, left [m]"; set zlabel "z, up [m]" rotate parallel
set view 62, 28, 0.85  # room for the key below
set view equal xyz
set xyplane at 0
# the key under the plot from its left (centred, its two columns ran off the image's left edge)
set key default; set key below left vertical maxrows 3 Left reverse font ",9"
set grid
splot geo index 0 using 1:2:3 with lines lc rgb "#B0B0B0" lw 1 title "everything at neutral", \
      geo index 1 using 1:2:($4 >= 0 ? $3 : 1/0) with lines lc rgb "#0072B2" lw 4 title "legs / rail (stroke) at the pose", \
      geo index 1 using 1:2:($4 == -2 ? $3 : 1/0) with lines lc rgb "black" lw 2 title "plate (joints) at the pose", \
      geo index 1 using 1:2:($4 == -3 ? $3 : 1/0) with lines lc rgb "#555555" lw 2 title "base joints", \
      geo index 1 using 1:2:($4 == -4 ? $3 : 1/0) with lines lc rgb "#E69F00" lw 2 title "yaw turntable rim and heading", \
      geo index 1 using 1:2:($4 == -1 ? $3 : 1/0) with linespoints lc rgb "#D55E00" dt 2 pt 7 ps 1 title "pivot (centre of rotation) to head"
if (has_slice) {
  unset view; set view map; unset zlabel; set size ratio -1
  set title "(roll, pitch) at heave 0: blue reachable, grey beyond a leg's stroke"
  set xlabel "roll, left side up [deg]"; set ylabel "pitch, nose up [deg]"
  set cblabel "largest stroke use at heave 0 (share of the half-stroke from neutral)"
  set cbrange [0:1.5]
  set palette defined (0 "#FFFFFF", 1 "#6BAED6", 1.0001 "#D0D0D0", 1.5 "#808080")
  set key default; set key below center maxrows 2 font ",9"
  set object 1 rect from -roll_box,-pitch_box to roll_box,pitch_box front fs empty border lc rgb "#0072B2" dt 2 lw 2
  set xrange [-1.5*roll_box:1.5*roll_box]; set yrange [-1.5*pitch_box:1.5*pitch_box]
  plot slice index 0 using 1:2:4 with image notitle, \
       tmp."_c0.dat" using 1:2 with lines lc rgb "black" lw 2 title "end of stroke, heave 0", \
       tmp."_c1.dat" using 1:2 with lines lc rgb "#009E73" lw 2 title sprintf("end of stroke, heave +%g m", heave_box/2), \
       tmp."_c2.dat" using 1:2 with lines lc rgb "#CC79A7" lw 2 title sprintf("end of stroke, heave -%g m", heave_box/2), \
       NaN with lines dt 2 lc rgb "#0072B2" lw 2 title sprintf("axis box ±%g deg roll, ±%g deg pitch", roll_box, pitch_box)
}
unset multiplot
