# The error-against-time study, written by warpchol-threshold-sweep: edit and
# rerun with `gnuplot THIS_FILE` from the directory the sweep ran in.
# Per configuration: seconds per step, the largest over the steps of the worst
# vertex's error max_i |x_i - x_i(ref)| and of the RMS error
# sqrt(mean_i |x_i - x_i(ref)|^2), both over max_i |x_i(ref) - X_i|; its label.

# WCC partial
$group0 << EOD
0.0551646 0.01257 0.00585008 "0.03" "0.03"
0.0535425 0.108663 0.051256 "0.1" "0.1"
0.0508598 0.202251 0.10203 "0.3" "0.3"
0.0240081 1 0.609487 "1 (diverged: 1.2)" "1"
EOD
# WCC delayed_top
$group1 << EOD
0.0547864 0.00189594 0.00126509 "0.3" "0.3"
0.0591874 0.00496116 0.00260977 "1" "1"
0.0640664 0.00178197 0.00100738 "inf" "inf"
EOD
# WCC preconditioned
$group2 << EOD
0.0663165 0.00181512 0.000806363 "0.3" "0.3"
0.0661471 0.00332932 0.00159948 "1" "1"
0.0579907 0.00178197 0.00100738 "inf" "inf"
EOD
# WCC auto
$group3 << EOD
0.0369318 0.00269797 0.00130741 "0.3" "0.3"
0.0343833 0.00104185 0.000607802 "1" "1"
0.0299358 0.000859106 0.000414027 "inf" "inf"
EOD
# WCC background
$group4 << EOD
0.0521373 0.00319393 0.00164931 "" ""
EOD
# WCC target error
$group5 << EOD
0.0612143 0.00299978 0.0015644 "0.3%" "0.3%"
0.0613346 0.00641602 0.00392988 "1%" "1%"
EOD
$front_max << EOD
0.0299358 0.000859106
EOD
$front_rms << EOD
0.0240081 0.609487
0.0299358 0.000414027
EOD

if (strstrt(GPVAL_TERMINALS, "pngcairo") > 0) {
  set terminal pngcairo size 1752,650 font ",11"
} else {
  set terminal png size 1752,650
}
set termoption noenhanced
set output "doc/study/plate_overloaded-t1.png"
set multiplot layout 1,2 margins 0.05137, 0.8562, 0.1077, 0.9154 spacing 0.06279 title "plate_overloaded: 17220 unknowns, 100 steps, 1 thread(s); error against the exact corotational run"
set logscale y
set format y "%.0e"
set grid
set key at screen 0.8647, screen 0.9154 left top vertical Left reverse
set xlabel "seconds per step"
set xrange [0:0.0716218]
set yrange [*:2]
set arrow 1 from 0.0462106, graph 0 to 0.0462106, graph 1 nohead dashtype 2 linewidth 2 linecolor rgb "black"
set label 1 "corotational (error 0)" at 0.0462106, graph 0.5 center rotate by 90 offset -1.2, 0
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
