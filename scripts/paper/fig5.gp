# The DANCERS paper's Fig. 5 and overhead claims, drawn from the fleet-size sweeps' medians
# (scripts/reproduce-paper):
#   gnuplot -e "csv='scale.csv'; delta='delta.csv'; delta_robots='4'; outdir='img'" fig5.gp
# STF of a module = its computation time per iteration / the iteration (the paper's Eq. 3;
# iterations of 10 ms). The paper's reported points are drawn in red.
set datafile separator ','
set datafile columnheaders
set terminal pngcairo size 1100,450 font ',10'
set grid
set logscale x 2
set xrange [0.8:160]
set xlabel 'robots (flocker image, robot\_count of the bench/scale layout)'
mode(p, col) = (strcol('pacing') eq p ? column(col) : NaN)
delta_ms = 10.0

set output outdir.'/paper_fig5_stf.png'
set multiplot layout 1,2 title "Fig. 5 of the paper, sitlnet's (medians of runs)"
set title 'lockstep pacing: STF of each module'
set ylabel 'STF'
set logscale y
set yrange [1e-4:10]
set key bottom right font ',9'
set arrow 1 from 20, graph 0 to 20, graph 1 nohead lc 'red' dt 2
set label 1 "paper: real time\nbelow about 20 robots" at 22, 4 tc 'red' font ',9'
plot csv u 1:(mode('lockstep','t_phy_ms')/delta_ms) w lp pt 5 t 'physics (T_{phy}/Δ)', \
     csv u 1:(mode('lockstep','t_net_ms')/delta_ms) w lp pt 9 t 'network (T_{net}/Δ)', \
     csv u 1:(mode('lockstep','t_total_ms')/delta_ms) w lp pt 7 lw 2 t 'co-simulation (T/Δ)', \
     csv u 1:(mode('lockstep','t_overhead_ms')/delta_ms) w lp pt 11 dt 2 t 'overhead (T_{overhead}/Δ)', \
     1 w l lc 'black' dt 3 t 'real time (STF 1)'
unset arrow 1
unset label 1
# In realtime pacing an iteration lasts Δ of wall time by design: what tells whether the host
# keeps up is the lag behind the wall clock, and the physics' share of the iteration.
set title 'realtime pacing: lag behind the wall clock, physics STF'
set ylabel 'ms (lag) or STF (physics)'
set yrange [1e-3:100]
plot csv u 1:(mode('realtime','lag_p99_ms')) w lp pt 7 lw 2 t 'lag p99 (ms)', \
     csv u 1:(mode('realtime','t_phy_ms')/delta_ms) w lp pt 5 t 'physics (T_{phy}/Δ)', \
     delta_ms w l lc 'black' dt 3 t 'one iteration (10 ms)'
unset multiplot

set output outdir.'/paper_overhead.png'
set multiplot layout 1,2 title "Overhead share T_{overhead}/T of an iteration, sitlnet's (medians of runs)"
set title 'vs fleet size (Δ = 10 ms)'
unset logscale y
set yrange [0:30]
set ylabel 'overhead share (%)'
set key top right font ',9'
# Lockstep only: in realtime pacing an iteration lasts Δ by design, so the share means nothing.
plot csv u 1:(mode('lockstep','overhead_share')*100) w lp pt 7 lw 2 t 'lockstep', \
     '+' u (32):(21) every ::0::0 w p pt 2 ps 2 lc 'red' t 'paper: 21 % at 32 robots (Gazebo)'
set title 'vs iteration length Δ (lockstep)'
set xlabel 'Δ (ms)'
set xrange [*:*]
set logscale x 2
plot delta u 1:($2*100) w lp pt 7 lw 2 t sprintf('lockstep, %s robots', delta_robots), \
     20 w l lc 'red' dt 2 t 'paper: "stays around 20 %"'
unset multiplot
