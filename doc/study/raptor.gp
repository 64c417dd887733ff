# The error-against-time study, written by warpchol-threshold-sweep: edit and
# rerun with `gnuplot THIS_FILE` from the directory the sweep ran in.
# Per configuration: seconds per step, the largest over the steps of the worst
# vertex's error max_i |x_i - x_i(ref)| and of the RMS error
# sqrt(mean_i |x_i - x_i(ref)|^2), both over max_i |x_i(ref) - X_i|; its label.

# WCC partial
$group0 << EOD
0.0527251 0.00138825 0.00036767 "0.03" "0.03"
0.0441448 0.00663497 0.00203811 "0.1" "0.1"
0.035886 0.0250535 0.00842061 "0.3" "0.3"
0.0295932 0.0964949 0.0376662 "1" "1"
0.021323 0.266263 0.106323 "3" "3"
0.010542 1 1 "inf (diverged: 4.7e+75)" "inf (diverged: 3.6e+74)"
EOD
# WCC delayed_top
$group1 << EOD
0.0332009 0.000610294 0.000169592 "0.3" "0.3"
0.0260973 0.00088874 0.000273333 "1" "1"
0.0115619 0.00270552 0.000643846 "inf" "inf"
EOD
# WCC preconditioned
$group2 << EOD
0.0388313 0.000625225 0.000156356 "0.3" "0.3"
0.033821 0.000887957 0.000260142 "1" "1"
0.0121142 0.00270552 0.000643846 "inf" "inf"
EOD
# WCC auto
$group3 << EOD
0.0262718 0.00225472 0.000504824 "0.3" "0.3"
0.0211347 0.00224929 0.000505899 "1" "1"
0.0120363 0.00270552 0.000643846 "inf" "inf"
EOD
# WCC target error
$group4 << EOD
0.0534561 0.00385513 0.00125564 "0.3%" "0.3%"
0.0437607 0.0137218 0.00441158 "1%" "1%"
0.0361978 0.0469032 0.0163957 "3%" "3%"
EOD
$front_max << EOD
0.0115619 0.00270552
0.0211347 0.00224929
0.0260973 0.00088874
0.0332009 0.000610294
EOD
$front_rms << EOD
0.0115619 0.000643846
0.0211347 0.000505899
0.0260973 0.000273333
0.0332009 0.000169592
0.0388313 0.000156356
EOD

if (strstrt(GPVAL_TERMINALS, "pngcairo") > 0) {
  set terminal pngcairo size 1752,650 font ",11"
} else {
  set terminal png size 1752,650
}
set termoption noenhanced
set output "doc/study/raptor.png"
set multiplot layout 1,2 margins 0.05137, 0.8562, 0.1077, 0.9154 spacing 0.06279 title "raptor: 16989 unknowns, 80 steps, 1 thread(s); error against the exact corotational run"
set logscale y
set format y "%.0e"
set grid
set key at screen 0.8647, screen 0.9154 left top vertical Left reverse
set xlabel "seconds per step"
set xrange [0:0.0577325]
set yrange [*:2]
set arrow 1 from 0.0503307, graph 0 to 0.0503307, graph 1 nohead dashtype 2 linewidth 2 linecolor rgb "black"
set label 1 "corotational (error 0)" at 0.0503307, graph 0.5 center rotate by 90 offset -1.2, 0
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
