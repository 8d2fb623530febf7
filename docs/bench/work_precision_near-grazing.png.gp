set terminal pngcairo size 900,650 font ',11' linewidth 1 pointscale 1
if (!exists('nsmodal_output')) nsmodal_output = 'work_precision_near-grazing.png'
set output nsmodal_output
set grid lt 1 lw 0.5 lc rgb '#E3E3E3'
set key samplen 2 spacing 1 noautotitle
set datafile separator ','
set logscale xy
set format y '10^{%T}'
set format x '10^{%T}'
set xlabel 'CPU time per run (s)'
set ylabel 'relative error of the final state (vs exact, root\_tol 1e-14)'
set key below
floor = 2.62579e-16
set arrow from graph 0, first floor to graph 1, first floor nohead lw 1 dt 3 lc rgb '#777777'
set label 'error 0 (drawn at this floor)' at graph 0.02, first floor offset 0, 0.7
plot 'work_precision.csv' using (strcol(1) eq 'near-grazing' && strcol(2) eq 'exact' && $4 > 0 ? $5 : 1/0):4 with linespoints lw 1.5 dt 1 pt 7 ps 0.8 lc rgb '#000000' title 'exact', \
  'work_precision.csv' using (strcol(1) eq 'near-grazing' && strcol(2) eq 'exact' && $4 == 0 ? $5 : 1/0):(floor) with points pt 7 ps 0.8 lw 1.5 lc rgb '#000000' notitle, \
  'work_precision.csv' using (strcol(1) eq 'near-grazing' && strcol(2) eq 'cvode-adams' && $4 > 0 ? $5 : 1/0):4 with linespoints lw 1.5 dt 4 pt 12 ps 0.8 lc rgb '#56B4E9' title 'cvode-adams', \
  'work_precision.csv' using (strcol(1) eq 'near-grazing' && strcol(2) eq 'cvode-adams' && $4 == 0 ? $5 : 1/0):(floor) with points pt 12 ps 0.8 lw 1.5 lc rgb '#56B4E9' notitle, \
  'work_precision.csv' using (strcol(1) eq 'near-grazing' && strcol(2) eq 'cvode-bdf' && $4 > 0 ? $5 : 1/0):4 with linespoints lw 1.5 dt 2 pt 4 ps 0.8 lc rgb '#0072B2' title 'cvode-bdf', \
  'work_precision.csv' using (strcol(1) eq 'near-grazing' && strcol(2) eq 'cvode-bdf' && $4 == 0 ? $5 : 1/0):(floor) with points pt 4 ps 0.8 lw 1.5 lc rgb '#0072B2' notitle, \
  'work_precision.csv' using (strcol(1) eq 'near-grazing' && strcol(2) eq 'cvode-plain' && $4 > 0 ? $5 : 1/0):4 with linespoints lw 1.5 dt 3 pt 10 ps 0.8 lc rgb '#009E73' title 'cvode-plain', \
  'work_precision.csv' using (strcol(1) eq 'near-grazing' && strcol(2) eq 'cvode-plain' && $4 == 0 ? $5 : 1/0):(floor) with points pt 10 ps 0.8 lw 1.5 lc rgb '#009E73' notitle, \
  'work_precision.csv' using (strcol(1) eq 'near-grazing' && strcol(2) eq 'moreau-jean' && $4 > 0 ? $5 : 1/0):4 with linespoints lw 1.5 dt 3 pt 8 ps 0.8 lc rgb '#B85000' title 'moreau-jean', \
  'work_precision.csv' using (strcol(1) eq 'near-grazing' && strcol(2) eq 'moreau-jean' && $4 == 0 ? $5 : 1/0):(floor) with points pt 8 ps 0.8 lw 1.5 lc rgb '#B85000' notitle, \
  'work_precision.csv' using (strcol(1) eq 'near-grazing' && $6 != $8 ? $5 : 1/0):($4 > 0 ? $4 : floor) with points pt 2 ps 1.5 lw 1.5 lc rgb '#000000' title 'wrong impact count'

