# Plots of bench/scale/run.sh: gnuplot -e "csv='docs/scale.csv'; outdir='docs/img'" plot.gp
set datafile separator ','
set datafile columnheaders
set terminal pngcairo size 800,500 font ',11'
set key top left
set logscale x 2
set xrange [0.8:160]
set xlabel 'robots (each running the flocker image)'
set grid
mode(p, col) = (strcol('pacing') eq p ? column(col) : NaN)

set output outdir.'/scale_stf.png'
set title 'Slow-down factor (wall / simulated time), medians of runs'
set ylabel 'STF (mean of iterations)'
set logscale y
plot csv u 1:(mode('lockstep','stf_mean')) w lp pt 7 lw 2 t 'lockstep, mean', \
     csv u 1:(mode('lockstep','stf_p99')) w lp pt 6 dt 2 t 'lockstep, p99', \
     csv u 1:(mode('realtime','stf_mean')) w lp pt 5 lw 2 t 'realtime, mean', \
     1 w l lc 'black' dt 3 t 'real time (STF 1)', \
     0.25 w l lc 'red' dt 3 t 'target lockstep 64 (0.25)'
unset logscale y

set output outdir.'/scale_overhead.png'
set title 'Co-simulation overhead share of T_{total}, medians of runs'
set ylabel 'overhead share (%)'
set yrange [0:*]
plot csv u 1:(mode('lockstep','overhead_share')*100) w lp pt 7 lw 2 t 'lockstep', \
     csv u 1:(mode('realtime','overhead_share')*100) w lp pt 5 lw 2 t 'realtime', \
     5 w l lc 'red' dt 3 t 'target at 32 robots (5 %)'

set output outdir.'/scale_cost.png'
set title 'Cost of one 10 ms iteration, lockstep (medians of run means)'
set ylabel 'wall ms per iteration'
set logscale y
set yrange [*:*]
plot csv u 1:(mode('lockstep','t_total_ms')) w lp pt 7 lw 2 t 'T_{total}', \
     csv u 1:(mode('lockstep','t_phy_ms')) w lp pt 5 t 'T_{phy} (physics + robots answering)', \
     csv u 1:(mode('lockstep','t_net_ms')) w lp pt 9 t 'T_{net} (medium)', \
     csv u 1:(mode('lockstep','t_overhead_ms')) w lp pt 11 t 'T_{overhead}'
unset logscale y

set output outdir.'/scale_lag.png'
set title 'Realtime pacing: iteration lag p99 and frames through the medium'
set ylabel 'lag p99 (ms)'
set logscale y
set yrange [0.5:*]
set y2label 'frames sent per wall second'
set y2tics
set ytics nomirror
set logscale y2
plot csv u 1:(mode('realtime','lag_p99_ms')) w lp pt 7 lw 2 t 'lag p99 (ms)', \
     2 w l lc 'red' dt 3 t 'target 2 ms', \
     csv u 1:(mode('realtime','sent_per_wall_s')) axes x1y2 w lp pt 5 t 'frames/s (right)'
