# The error-against-time study, written by warpchol-threshold-sweep: edit and
# rerun with `gnuplot THIS_FILE` from the directory the sweep ran in.
# Per configuration: seconds per step, the largest over the steps of the worst
# vertex's error max_i |x_i - x_i(ref)| and of the RMS error
# sqrt(mean_i |x_i - x_i(ref)|^2), both over max_i |x_i(ref) - X_i|; its label.

# WCC partial
$group0 << EOD
0.0380789 0.0704223 0.0411077 "0.03" "0.03"
0.03592 0.248981 0.150696 "0.1" "0.1"
0.0276122 0.965723 0.497768 "0.3" "0.3"
0.0135692 1 0.938817 "1 (diverged: 1.8)" "1"
EOD
# WCC delayed_top
$group1 << EOD
0.0333506 0.00358648 0.00182701 "0.3" "0.3"
0.03791 0.0050184 0.00245958 "1" "1"
0.0456353 0.00206702 0.00105486 "inf" "inf"
EOD
# WCC preconditioned
$group2 << EOD
0.0382282 0.00336942 0.00182139 "0.3" "0.3"
0.0373285 0.00421038 0.00197432 "1" "1"
0.0449772 0.00206702 0.00105486 "inf" "inf"
EOD
# WCC auto
$group3 << EOD
0.0236339 0.00143309 0.000717613 "0.3" "0.3"
0.0245192 0.00407518 0.00225209 "1" "1"
0.0196451 0.00122552 0.000564468 "inf" "inf"
EOD
# WCC background
$group4 << EOD
0.0336994 0.00247006 0.00114816 "" ""
EOD
# WCC target error
$group5 << EOD
0.0387154 0.00320581 0.0019632 "0.3%" "0.3%"
0.0380862 0.00684251 0.0041838 "1%" "1%"
EOD
$front_max << EOD
0.0196451 0.00122552
EOD
$front_rms << EOD
0.0135692 0.938817
0.0196451 0.000564468
EOD

if (strstrt(GPVAL_TERMINALS, "pngcairo") > 0) {
  set terminal pngcairo size 1752,650 font ",11"
} else {
  set terminal png size 1752,650
}
set termoption noenhanced
set output "doc/study/plate-t2.png"
set multiplot layout 1,2 margins 0.05137, 0.8562, 0.1077, 0.9154 spacing 0.06279 title "plate: 17220 unknowns, 100 steps, 2 thread(s); error against the exact corotational run"
set logscale y
set format y "%.0e"
set grid
set key at screen 0.8647, screen 0.9154 left top vertical Left reverse
set xlabel "seconds per step"
set xrange [0:0.0492862]
set yrange [*:2]
set arrow 1 from 0.0304754, graph 0 to 0.0304754, graph 1 nohead dashtype 2 linewidth 2 linecolor rgb "black"
set label 1 "corotational (error 0)" at 0.0304754, graph 0.5 center rotate by 90 offset -1.2, 0
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
