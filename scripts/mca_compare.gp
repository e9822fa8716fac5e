# Perceived surge specific force (otolith, x) and pitch rate (canal, y) on the speed cushion,
# vehicle vs platform for each algorithm (scripts/mca-compare.sh sets dir).
set terminal pngcairo size 1200,800 font ",10"
set datafile separator ","
set key autotitle columnhead top right
set multiplot layout 2,1 title "speed cushion: perceived motion, vehicle vs platform"
set ylabel "perceived f_x [m/s^2]"
plot dir."/speed_cushion/washout/trial.csv" using "t_s":"vest_true_oto_x_mps2" with lines lw 2 lc rgb "black" title "vehicle", \
     dir."/speed_cushion/washout/trial.csv" using "t_s":"vest_plat_oto_x_mps2" with lines lc rgb "#0072B2" title "washout", \
     dir."/speed_cushion/mpc/trial.csv" using "t_s":"vest_plat_oto_x_mps2" with lines lc rgb "#D55E00" title "MPC, no preview", \
     dir."/speed_cushion/mpc-preview/trial.csv" using "t_s":"vest_plat_oto_x_mps2" with lines lc rgb "#009E73" title "MPC, preview", \
     dir."/speed_cushion/offline/trial.csv" using "t_s":"vest_plat_oto_x_mps2" with lines dt 2 lc rgb "#CC79A7" title "offline optimum"
set ylabel "perceived ω_y [rad/s]"
set xlabel "t [s]"
plot dir."/speed_cushion/washout/trial.csv" using "t_s":"vest_true_scc_y_radps" with lines lw 2 lc rgb "black" title "vehicle", \
     dir."/speed_cushion/washout/trial.csv" using "t_s":"vest_plat_scc_y_radps" with lines lc rgb "#0072B2" title "washout", \
     dir."/speed_cushion/mpc/trial.csv" using "t_s":"vest_plat_scc_y_radps" with lines lc rgb "#D55E00" title "MPC, no preview", \
     dir."/speed_cushion/mpc-preview/trial.csv" using "t_s":"vest_plat_scc_y_radps" with lines lc rgb "#009E73" title "MPC, preview", \
     dir."/speed_cushion/offline/trial.csv" using "t_s":"vest_plat_scc_y_radps" with lines dt 2 lc rgb "#CC79A7" title "offline optimum"
unset multiplot
