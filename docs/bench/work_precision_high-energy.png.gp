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
floor = 9.91367e-14
set arrow from graph 0, first floor to graph 1, first floor nohead dt 3 lc rgb '#999999'
set label 'error 0 (drawn at this floor)' at graph 0.02, first floor offset 0, 0.7 font ',8'
plot for [i in 'exact cvode-adams cvode-bdf cvode-plain moreau-jean'] 'work_precision.csv' using (strcol(1) eq 'high-energy' && strcol(2) eq i && $4 > 0 ? $5 : 1/0):4 with linespoints lw 2 pt 7 title i, \
  for [i in 'exact cvode-adams cvode-bdf cvode-plain moreau-jean'] '' using (strcol(1) eq 'high-energy' && strcol(2) eq i && $4 == 0 ? $5 : 1/0):(floor) with points pt 6 ps 1.5 lw 2 lc rgb '#555555' notitle, \
  '' using (strcol(1) eq 'high-energy' && $6 != $8 ? $5 : 1/0):($4 > 0 ? $4 : floor) with points pt 2 ps 2.5 lw 2 lc rgb 'black' title 'wrong impact count'

