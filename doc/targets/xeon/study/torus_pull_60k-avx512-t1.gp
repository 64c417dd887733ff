# The error-against-time study, written by warpchol-threshold-sweep: edit and
# rerun with `gnuplot THIS_FILE` from the directory the sweep ran in.
# Per configuration: seconds per step, the largest over the steps of the worst
# vertex's error max_i |x_i - x_i(ref)| and of the RMS error
# sqrt(mean_i |x_i - x_i(ref)|^2), both over max_i |x_i(ref) - X_i|; its label.

# WCC partial
$group0 << EOD
0.477531 0.00356364 0.0010711 "0.3" "0.3"
0.415452 0.0151297 0.00385526 "1" "1"
0.061654 0.358343 0.067763 "inf" "inf"
EOD
# WCC auto
$group1 << EOD
0.155624 0.000364828 1.84219e-05 "0.3" "0.3"
0.141416 0.000364828 1.94185e-05 "1" "1"
0.113948 0.000364828 2.96134e-05 "inf" "inf"
EOD
$front_max << EOD
0.061654 0.358343
0.113948 0.000364828
EOD
$front_rms << EOD
0.061654 0.067763
0.113948 2.96134e-05
0.141416 1.94185e-05
0.155624 1.84219e-05
EOD

if (strstrt(GPVAL_TERMINALS, "pngcairo") > 0) {
  set terminal pngcairo size 1698,650 font ",11"
} else {
  set terminal png size 1698,650
}
set termoption noenhanced
set output "doc/targets/xeon/study/torus_pull_60k-avx512-t1.png"
set multiplot layout 1,2 margins 0.053, 0.8834, 0.1077, 0.9154 spacing 0.06478 title "torus_pull_60k: 64095 unknowns, 10 steps, 1 thread(s); error against the exact corotational run"
set logscale y
set format y "%.0e"
set grid
set key at screen 0.8922, screen 0.9154 left top vertical Left reverse
set xlabel "seconds per step"
set xrange [0:0.928916]
set arrow 1 from 0.860108, graph 0 to 0.860108, graph 1 nohead dashtype 2 linewidth 2 linecolor rgb "black"
set label 1 "corotational (error 0)" at 0.860108, graph 0.5 center rotate by 90 offset -1.2, 0
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
