set terminal pngcairo size 900,650 font ',11'
if (!exists('nsmodal_output')) nsmodal_output = 'work_precision_high-energy.png'
set output nsmodal_output
set datafile separator ','
set logscale xy
set format y '10^{%T}'
set format x '10^{%T}'
set xlabel 'CPU time per run (s)'
set ylabel 'relative error of the final state (vs exact, root\_tol 1e-14)'
set title 'work-precision: high-energy'
set key outside right
set grid
plot for [i in 'exact cvode-adams cvode-bdf cvode-plain moreau-jean'] 'work_precision.csv' using (strcol(1) eq 'high-energy' && strcol(2) eq i && $4 > 0 ? $5 : 1/0):4 with linespoints lw 2 pt 7 title i

