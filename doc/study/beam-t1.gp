# The error-against-time study, written by warpchol-threshold-sweep: edit and
# rerun with `gnuplot THIS_FILE` from the directory the sweep ran in.
# Per configuration: seconds per step, the largest over the steps of the worst
# vertex's error max_i |x_i - x_i(ref)| and of the RMS error
# sqrt(mean_i |x_i - x_i(ref)|^2), both over max_i |x_i(ref) - X_i|; its label.

# WCC partial
$group0 << EOD
0.0179228 0.0385473 0.0195282 "0.03" "0.03"
0.0167825 0.148757 0.0752792 "0.1" "0.1"
0.00885832 0.481913 0.242526 "0.3" "0.3"
0.00479611 0.506458 0.248093 "1" "1"
EOD
# WCC delayed_top
$group1 << EOD
0.013092 0.000952132 0.000467813 "0.3" "0.3"
0.0127422 0.000272153 0.000134329 "1" "1"
0.0141012 0.000806746 0.000393589 "inf" "inf"
EOD
# WCC preconditioned
$group2 << EOD
0.0163305 0.00101109 0.000505002 "0.3" "0.3"
0.0140003 0.000472302 0.000238402 "1" "1"
0.0136135 0.000806746 0.000393589 "inf" "inf"
EOD
# WCC auto
$group3 << EOD
0.0101802 0.000368324 0.000186324 "0.3" "0.3"
0.00903636 0.000908685 0.000459501 "1" "1"
0.00763188 0.000378638 0.000193034 "inf" "inf"
EOD
# WCC background
$group4 << EOD
0.0130203 0.000372542 0.000189888 "" ""
EOD
# WCC target error
$group5 << EOD
0.0190376 0.0133891 0.0073801 "0.3%" "0.3%"
0.0184099 0.026218 0.0112916 "1%" "1%"
EOD
$front_max << EOD
0.00479611 0.506458
0.00763188 0.000378638
0.0101802 0.000368324
0.0127422 0.000272153
EOD
$front_rms << EOD
0.00479611 0.248093
0.00763188 0.000193034
0.0101802 0.000186324
0.0127422 0.000134329
EOD

if (strstrt(GPVAL_TERMINALS, "pngcairo") > 0) {
  set terminal pngcairo size 1752,650 font ",11"
} else {
  set terminal png size 1752,650
}
set termoption noenhanced
set output "doc/study/beam-t1.png"
set multiplot layout 1,2 margins 0.05137, 0.8562, 0.1077, 0.9154 spacing 0.06279 title "beam: 8544 unknowns, 100 steps, 1 thread(s); error against the exact corotational run"
set logscale y
set format y "%.0e"
set grid
set key at screen 0.8647, screen 0.9154 left top vertical Left reverse
set xlabel "seconds per step"
set xrange [0:0.0205606]
set arrow 1 from 0.0164976, graph 0 to 0.0164976, graph 1 nohead dashtype 2 linewidth 2 linecolor rgb "black"
set label 1 "corotational (error 0)" at 0.0164976, graph 0.5 center rotate by 90 offset -1.2, 0
set ylabel "worst vertex error over the largest displacement (max over steps)"
plot $front_max using 1:2 with lines linewidth 2 linecolor rgb "gray40" title "Pareto front", \
     $group0 using 1:2 with points pointtype 5 pointsize 1.6 linecolor rgb "#9400d3" title "WCC partial", \
     $group0 using 1:2:4 with labels left offset 0.8, 0.7 textcolor rgb "#9400d3" notitle, \
     $group1 using 1:2 with points pointtype 7 pointsize 1.6 linecolor rgb "#009e73" title "WCC delayed_top", \
     $group1 using 1:2:4 with labels left offset 0.8, -0.7 textcolor rgb "#009e73" notitle, \
     $group2 using 1:2 with points pointtype 9 pointsize 1.6 linecolor rgb "#56b4e9" title "WCC preconditioned", \
     $group2 using 1:2:4 with labels right offset -0.8, 0.7 textcolor rgb "#56b4e9" notitle, \
     $group3 using 1:2 with points pointtype 11 pointsize 1.6 linecolor rgb "#e69f00" title "WCC auto", \
     $group3 using 1:2:4 with labels right offset -0.8, -0.7 textcolor rgb "#e69f00" notitle, \
     $group4 using 1:2 with points pointtype 13 pointsize 1.6 linecolor rgb "#f0e442" title "WCC background", \
     $group4 using 1:2:4 with labels left offset 0.8, 0.7 textcolor rgb "#f0e442" notitle, \
     $group5 using 1:2 with points pointtype 15 pointsize 1.6 linecolor rgb "#0072b2" title "WCC target error", \
     $group5 using 1:2:4 with labels left offset 0.8, -0.7 textcolor rgb "#0072b2" notitle
unset key
set ylabel "RMS error over the largest displacement (max over steps)"
plot $front_rms using 1:2 with lines linewidth 2 linecolor rgb "gray40" title "Pareto front", \
     $group0 using 1:3 with points pointtype 5 pointsize 1.6 linecolor rgb "#9400d3" title "WCC partial", \
     $group0 using 1:3:5 with labels left offset 0.8, 0.7 textcolor rgb "#9400d3" notitle, \
     $group1 using 1:3 with points pointtype 7 pointsize 1.6 linecolor rgb "#009e73" title "WCC delayed_top", \
     $group1 using 1:3:5 with labels left offset 0.8, -0.7 textcolor rgb "#009e73" notitle, \
     $group2 using 1:3 with points pointtype 9 pointsize 1.6 linecolor rgb "#56b4e9" title "WCC preconditioned", \
     $group2 using 1:3:5 with labels right offset -0.8, 0.7 textcolor rgb "#56b4e9" notitle, \
     $group3 using 1:3 with points pointtype 11 pointsize 1.6 linecolor rgb "#e69f00" title "WCC auto", \
     $group3 using 1:3:5 with labels right offset -0.8, -0.7 textcolor rgb "#e69f00" notitle, \
     $group4 using 1:3 with points pointtype 13 pointsize 1.6 linecolor rgb "#f0e442" title "WCC background", \
     $group4 using 1:3:5 with labels left offset 0.8, 0.7 textcolor rgb "#f0e442" notitle, \
     $group5 using 1:3 with points pointtype 15 pointsize 1.6 linecolor rgb "#0072b2" title "WCC target error", \
     $group5 using 1:3:5 with labels left offset 0.8, -0.7 textcolor rgb "#0072b2" notitle
unset multiplot
