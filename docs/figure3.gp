# The paper's Figure 3 from figure3.dat (written by `evaluate figure3`):
# gnuplot -e "data='docs/figure3.dat'; out='docs/figure3.png'" docs/figure3.gp
set terminal pngcairo size 1500,480 font ",11"
set output out
set multiplot layout 1,3
set logscale xy
set xrange [0.0008:0.13]
set xlabel "noise standard deviation"
set ylabel "mean distance to the true surface"
set key top left
set grid
do for [i=0:2] {
  set title word("plane sphere cube", i + 1)
  plot data index i using 1:2 with linespoints pt 1 lc rgb "#1f77b4" title "noisy input", \
       data index i using 1:3 with linespoints pt 7 lc rgb "#ff7f0e" title "Tikhonov (default)", \
       data index i using 1:4 with linespoints pt 2 lc rgb "#d62728" title "TV (default)", \
       data index i using 1:5 with lines dt 2 lc rgb "#ff7f0e" title "Tikhonov (best gamma)", \
       data index i using 1:6 with lines dt 2 lc rgb "#d62728" title "TV (best gamma)"
}
unset multiplot
