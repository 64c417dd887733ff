# The error-against-time study, written by warpchol-threshold-sweep: edit and
# rerun with `gnuplot THIS_FILE` from the directory the sweep ran in.
# Per configuration: seconds per step, the largest over the steps of the worst
# vertex's error max_i |x_i - x_i(ref)| and of the RMS error
# sqrt(mean_i |x_i - x_i(ref)|^2), both over max_i |x_i(ref) - X_i|; its label.

# WCC partial
$group0 << EOD
0.0682095 0.202245 0.103475 "0.3" "0.3"
0.0246052 1 0.609487 "1 (diverged: 1.2)" "1"
EOD
# WCC auto
$group1 << EOD
0.0339353 0.00145799 0.000871199 "0.3" "0.3"
0.0293579 0.00167991 0.000711783 "1" "1"
0.0207063 0.00581776 0.00295251 "inf" "inf"
EOD
$front_max << EOD
0.0207063 0.00581776
0.0293579 0.00167991
0.0339353 0.00145799
EOD
$front_rms << EOD
0.0207063 0.00295251
0.0293579 0.000711783
EOD

if (strstrt(GPVAL_TERMINALS, "pngcairo") > 0) {
  set terminal pngcairo size 1698,650 font ",11"
} else {
  set terminal png size 1698,650
}
set termoption noenhanced
set output "doc/targets/xeon/study/plate_overloaded-avx2-t2.png"
set multiplot layout 1,2 margins 0.053, 0.8834, 0.1077, 0.9154 spacing 0.06478 title "plate_overloaded: 17220 unknowns, 100 steps, 2 thread(s); error against the exact corotational run"
set logscale y
set format y "%.0e"
set grid
set key at screen 0.8922, screen 0.9154 left top vertical Left reverse
set xlabel "seconds per step"
set xrange [0:0.0736662]
set yrange [*:2]
set arrow 1 from 0.0579474, graph 0 to 0.0579474, graph 1 nohead dashtype 2 linewidth 2 linecolor rgb "black"
set label 1 "corotational (error 0)" at 0.0579474, graph 0.5 center rotate by 90 offset -1.2, 0
set ylabel "worst vertex error over the largest displacement (max over steps)"
plot $front_max using 1:2 with lines linewidth 2 linecolor rgb "gray40" title "Pareto front", \
     $group0 using 1:2 with points pointtype 5 pointsize 1.6 linecolor rgb "#9400d3" title "WCC partial", \
     $group0 using 1:2:4 with labels left offset 0.8, 0.7 textcolor rgb "#9400d3" notitle, \
     $group1 using 1:2 with points pointtype 7 pointsize 1.6 linecolor rgb "#009e73" title "WCC auto", \
     $group1 using 1:2:4 with labels left offset 0.8, -0.7 textcolor rgb "#009e73" notitle
unset key
set ylabel "RMS error over the largest displacement (max over steps)"
plot $front_rms using 1:2 with lines linewidth 2 linecolor rgb "gray40" title "Pareto front", \
     $group0 using 1:3 with points pointtype 5 pointsize 1.6 linecolor rgb "#9400d3" title "WCC partial", \
     $group0 using 1:3:5 with labels left offset 0.8, 0.7 textcolor rgb "#9400d3" notitle, \
     $group1 using 1:3 with points pointtype 7 pointsize 1.6 linecolor rgb "#009e73" title "WCC auto", \
     $group1 using 1:3:5 with labels left offset 0.8, -0.7 textcolor rgb "#009e73" notitle
unset multiplot
