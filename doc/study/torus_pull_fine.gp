# The error-against-time study, written by warpchol-threshold-sweep: edit and
# rerun with `gnuplot THIS_FILE` from the directory the sweep ran in.
# Per configuration: seconds per step, the largest over the steps of the worst
# vertex's error max_i |x_i - x_i(ref)| and of the RMS error
# sqrt(mean_i |x_i - x_i(ref)|^2), both over max_i |x_i(ref) - X_i|; its label.

# WCC partial
$group0 << EOD
0.0343231 0.00121876 0.00067165 "0.03" "0.03"
0.0276167 0.00450525 0.00283519 "0.1" "0.1"
0.022672 0.0161133 0.00868627 "0.3" "0.3"
0.0170088 0.0633659 0.0348156 "1" "1"
0.0127674 0.098221 0.0521267 "3" "3"
0.00396178 0.110339 0.0583573 "inf" "inf"
EOD
# WCC delayed_top
$group1 << EOD
0.0183706 0.000705587 0.000306944 "0.3" "0.3"
0.0168037 0.000752632 0.000320605 "1" "1"
0.00647442 0.000501095 0.000205999 "inf" "inf"
EOD
# WCC preconditioned
$group2 << EOD
0.0310923 0.000703097 0.000305437 "0.3" "0.3"
0.024195 0.00073673 0.000322758 "1" "1"
0.00737512 0.000501095 0.000205999 "inf" "inf"
EOD
# WCC auto
$group3 << EOD
0.0171058 0.000447142 0.000215527 "0.3" "0.3"
0.0131898 0.000313261 0.00015512 "1" "1"
0.00677828 0.000501095 0.000205999 "inf" "inf"
EOD
# WCC target error
$group4 << EOD
0.0437778 0.0016588 0.000994027 "0.3%" "0.3%"
0.0312382 0.00542029 0.00352566 "1%" "1%"
0.0253444 0.0230799 0.0136745 "3%" "3%"
EOD
$front_max << EOD
0.00396178 0.110339
0.00647442 0.000501095
0.0131898 0.000313261
EOD
$front_rms << EOD
0.00396178 0.0583573
0.00647442 0.000205999
0.0131898 0.00015512
EOD

if (strstrt(GPVAL_TERMINALS, "pngcairo") > 0) {
  set terminal pngcairo size 1752,650 font ",11"
} else {
  set terminal png size 1752,650
}
set termoption noenhanced
set output "doc/study/torus_pull_fine.png"
set multiplot layout 1,2 margins 0.05137, 0.8562, 0.1077, 0.9154 spacing 0.06279 title "torus_pull_fine: 10035 unknowns, 100 steps, 1 thread(s); error against the exact corotational run"
set logscale y
set format y "%.0e"
set grid
set key at screen 0.8647, screen 0.9154 left top vertical Left reverse
set xlabel "seconds per step"
set xrange [0:0.04728]
set arrow 1 from 0.0395705, graph 0 to 0.0395705, graph 1 nohead dashtype 2 linewidth 2 linecolor rgb "black"
set label 1 "corotational (error 0)" at 0.0395705, graph 0.5 center rotate by 90 offset -1.2, 0
set ylabel "worst vertex error over the largest displacement (max over steps)"
plot $front_max using 1:2 with lines linewidth 2 linecolor rgb "gray40" title "Pareto front", \
     $group0 using 1:2 with points pointtype 5 pointsize 1.6 linecolor 1 title "WCC partial", \
     $group0 using 1:2:4 with labels left offset 0.8, 0.7 textcolor lt 1 notitle, \
     $group1 using 1:2 with points pointtype 7 pointsize 1.6 linecolor 2 title "WCC delayed_top", \
     $group1 using 1:2:4 with labels left offset 0.8, -0.7 textcolor lt 2 notitle, \
     $group2 using 1:2 with points pointtype 9 pointsize 1.6 linecolor 3 title "WCC preconditioned", \
     $group2 using 1:2:4 with labels right offset -0.8, 0.7 textcolor lt 3 notitle, \
     $group3 using 1:2 with points pointtype 11 pointsize 1.6 linecolor 4 title "WCC auto", \
     $group3 using 1:2:4 with labels right offset -0.8, -0.7 textcolor lt 4 notitle, \
     $group4 using 1:2 with points pointtype 5 pointsize 1.6 linecolor 5 title "WCC target error", \
     $group4 using 1:2:4 with labels left offset 0.8, 0.7 textcolor lt 5 notitle
unset key
set ylabel "RMS error over the largest displacement (max over steps)"
plot $front_rms using 1:2 with lines linewidth 2 linecolor rgb "gray40" title "Pareto front", \
     $group0 using 1:3 with points pointtype 5 pointsize 1.6 linecolor 1 title "WCC partial", \
     $group0 using 1:3:5 with labels left offset 0.8, 0.7 textcolor lt 1 notitle, \
     $group1 using 1:3 with points pointtype 7 pointsize 1.6 linecolor 2 title "WCC delayed_top", \
     $group1 using 1:3:5 with labels left offset 0.8, -0.7 textcolor lt 2 notitle, \
     $group2 using 1:3 with points pointtype 9 pointsize 1.6 linecolor 3 title "WCC preconditioned", \
     $group2 using 1:3:5 with labels right offset -0.8, 0.7 textcolor lt 3 notitle, \
     $group3 using 1:3 with points pointtype 11 pointsize 1.6 linecolor 4 title "WCC auto", \
     $group3 using 1:3:5 with labels right offset -0.8, -0.7 textcolor lt 4 notitle, \
     $group4 using 1:3 with points pointtype 5 pointsize 1.6 linecolor 5 title "WCC target error", \
     $group4 using 1:3:5 with labels left offset 0.8, 0.7 textcolor lt 5 notitle
unset multiplot
