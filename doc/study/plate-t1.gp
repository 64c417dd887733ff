# The error-against-time study, written by warpchol-threshold-sweep: edit and
# rerun with `gnuplot THIS_FILE` from the directory the sweep ran in.
# Per configuration: seconds per step, the largest over the steps of the worst
# vertex's error max_i |x_i - x_i(ref)| and of the RMS error
# sqrt(mean_i |x_i - x_i(ref)|^2), both over max_i |x_i(ref) - X_i|; its label.

# WCC partial
$group0 << EOD
0.055566 0.0700484 0.0408487 "0.03" "0.03"
0.0532809 0.249253 0.151011 "0.1" "0.1"
0.0456222 0.965495 0.49765 "0.3" "0.3"
0.0230486 1 0.938817 "1 (diverged: 1.8)" "1"
EOD
# WCC delayed_top
$group1 << EOD
0.0609735 0.00238653 0.00118587 "0.3" "0.3"
0.0644928 0.00519729 0.00256393 "1" "1"
0.0896108 0.00200585 0.00101283 "inf" "inf"
EOD
# WCC preconditioned
$group2 << EOD
0.0649573 0.00423766 0.0022774 "0.3" "0.3"
0.0679855 0.00351724 0.00166382 "1" "1"
0.0868215 0.00200585 0.00101283 "inf" "inf"
EOD
# WCC auto
$group3 << EOD
0.0386567 0.00185143 0.00106996 "0.3" "0.3"
0.0350817 0.00251261 0.00122031 "1" "1"
0.0314627 0.00125146 0.00054386 "inf" "inf"
EOD
# WCC background
$group4 << EOD
0.0513129 0.00208749 0.000942322 "" ""
EOD
# WCC target error
$group5 << EOD
0.060574 0.00320581 0.0019632 "0.3%" "0.3%"
0.0613658 0.00684251 0.0041838 "1%" "1%"
EOD
$front_max << EOD
0.0314627 0.00125146
EOD
$front_rms << EOD
0.0230486 0.938817
0.0314627 0.00054386
EOD

if (strstrt(GPVAL_TERMINALS, "pngcairo") > 0) {
  set terminal pngcairo size 1752,650 font ",11"
} else {
  set terminal png size 1752,650
}
set termoption noenhanced
set output "doc/study/plate-t1.png"
set multiplot layout 1,2 margins 0.05137, 0.8562, 0.1077, 0.9154 spacing 0.06279 title "plate: 17220 unknowns, 100 steps, 1 thread(s); error against the exact corotational run"
set logscale y
set format y "%.0e"
set grid
set key at screen 0.8647, screen 0.9154 left top vertical Left reverse
set xlabel "seconds per step"
set xrange [0:0.0967797]
set yrange [*:2]
set arrow 1 from 0.0470478, graph 0 to 0.0470478, graph 1 nohead dashtype 2 linewidth 2 linecolor rgb "black"
set label 1 "corotational (error 0)" at 0.0470478, graph 0.5 center rotate by 90 offset -1.2, 0
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
