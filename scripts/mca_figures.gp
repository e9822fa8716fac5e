# The cueing figures of docs/mca.md from scripts/mca_figures.py's data (scripts/mca-figures.sh
# sets dir, images and commit).
set terminal pngcairo size 1400,700 font ",10" noenhanced
set style data histograms
set style histogram clustered gap 1
set style fill solid 0.85 border -1
set boxwidth 0.9
set key top left
set xtics rotate by -30 nomirror
set grid ytics
set bmargin 9
set rmargin 10
set yrange [0:*]

set output images."/mca_cueing_error.png"
set title "Perceived-motion error, vehicle vs platform: RMS over otolith [m/s^2] and canal [rad/s x 10] channels\n".\
          "data: scripts/mca-figures.sh, every shipped scene on its platform and on stewart6dof, pwsim ".commit
set ylabel "RMS error [-]"
plot dir."/error.dat" using 2:xtic(1) title "washout" lc rgb "#0072B2", \
     "" using 3 title "MPC, no preview" lc rgb "#D55E00", \
     "" using 4 title "offline ceiling" lc rgb "#009E73"

set output images."/mca_cueing_xcorr.png"
set multiplot layout 1,2 title "Correlation and delay, vehicle vs platform, the same six channels stacked\n".\
    "data: scripts/mca-figures.sh, pwsim ".commit
set title "cross-correlation peak"
set ylabel "normalised cross-correlation [-]"
set yrange [0:1]
plot dir."/xcorr.dat" using 2:xtic(1) title "washout" lc rgb "#0072B2", \
     "" using 3 title "MPC, no preview" lc rgb "#D55E00", \
     "" using 4 title "offline ceiling" lc rgb "#009E73"
set title "its lag (> 0: platform late)"
set ylabel "lag [ms]"
set yrange [*:*]
plot dir."/xcorr.dat" using 5:xtic(1) title "washout" lc rgb "#0072B2", \
     "" using 6 title "MPC, no preview" lc rgb "#D55E00", \
     "" using 7 title "offline ceiling" lc rgb "#009E73"
unset multiplot

platforms = system("cat ".dir."/platforms.txt")
set output images."/mca_cueing_stroke.png"
set multiplot layout 1,words(platforms) title "Stroke use per actuator (share of the half-stroke from neutral, largest over the shipped scenes)\n".\
    "against what the platform file's axis boxes ask at their corners (> 1: beyond the stroke); data: scripts/mca-figures.sh, pwsim ".commit
set yrange [0:*]
set ylabel "stroke use [-]"
do for [i = 1:words(platforms)] {
  p = word(platforms, i)
  set title p
  plot dir."/stroke_".p.".dat" using 2:xtic(1) title "washout" lc rgb "#0072B2", \
       "" using 3 title "MPC, no preview" lc rgb "#D55E00", \
       "" using 4 title "axis boxes ask" lc rgb "#BBBBBB", \
       1 with lines dt 2 lc rgb "black" notitle
}
unset multiplot
