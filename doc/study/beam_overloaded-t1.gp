# The error-against-time study, written by warpchol-threshold-sweep: edit and
# rerun with `gnuplot THIS_FILE` from the directory the sweep ran in.
# Per configuration: seconds per step, the largest over the steps of the worst
# vertex's error max_i |x_i - x_i(ref)| and of the RMS error
# sqrt(mean_i |x_i - x_i(ref)|^2), both over max_i |x_i(ref) - X_i|; its label.

# WCC partial
$group0 << EOD
0.0206942 0.0111626 0.00582473 "0.03" "0.03"
0.0199075 0.076722 0.0241797 "0.1" "0.1"
0.0190985 0.412973 0.236376 "0.3" "0.3"
0.0106782 1 0.720837 "1 (diverged: 1.4)" "1"
EOD
# WCC delayed_top
$group1 << EOD
0.0193782 0.00437722 0.00163765 "0.3" "0.3"
0.0184512 0.000844422 0.000351722 "1" "1"
0.0130639 0.000484662 0.000178099 "inf" "inf"
EOD
# WCC preconditioned
$group2 << EOD
0.022548 0.00265633 0.00128752 "0.3" "0.3"
0.0213969 0.00104904 0.000354506 "1" "1"
0.0134333 0.000484662 0.000178099 "inf" "inf"
EOD
# WCC auto
$group3 << EOD
0.0140636 0.00211618 0.000884239 "0.3" "0.3"
0.0131335 0.00258425 0.0013965 "1" "1"
0.00989926 0.00132674 0.000474464 "inf" "inf"
EOD
# WCC background
$group4 << EOD
0.0181267 0.00184922 0.000606096 "" ""
EOD
# WCC target error
$group5 << EOD
0.0229946 0.00282715 0.00145815 "0.3%" "0.3%"
0.022709 0.0065085 0.00368278 "1%" "1%"
EOD
$front_max << EOD
0.00989926 0.00132674
0.0130639 0.000484662
EOD
$front_rms << EOD
0.00989926 0.000474464
0.0130639 0.000178099
EOD

if (strstrt(GPVAL_TERMINALS, "pngcairo") > 0) {
  set terminal pngcairo size 1752,650 font ",11"
} else {
  set terminal png size 1752,650
}
set termoption noenhanced
set output "doc/study/beam_overloaded-t1.png"
set multiplot layout 1,2 margins 0.05137, 0.8562, 0.1077, 0.9154 spacing 0.06279 title "beam_overloaded: 8544 unknowns, 100 steps, 1 thread(s); error against the exact corotational run"
set logscale y
set format y "%.0e"
set grid
set key at screen 0.8647, screen 0.9154 left top vertical Left reverse
set xlabel "seconds per step"
set xrange [0:0.0248342]
set yrange [*:2]
set arrow 1 from 0.0165966, graph 0 to 0.0165966, graph 1 nohead dashtype 2 linewidth 2 linecolor rgb "black"
set label 1 "corotational (error 0)" at 0.0165966, graph 0.5 center rotate by 90 offset -1.2, 0
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
