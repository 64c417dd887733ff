# The error-against-time study, written by warpchol-threshold-sweep: edit and
# rerun with `gnuplot THIS_FILE` from the directory the sweep ran in.
# Per configuration: seconds per step, the largest over the steps of the worst
# vertex's error max_i |x_i - x_i(ref)| and of the RMS error
# sqrt(mean_i |x_i - x_i(ref)|^2), both over max_i |x_i(ref) - X_i|; its label.

# WCC partial
$group0 << EOD
0.0255673 0.358343 0.067763 "inf" "inf"
EOD
# WCC auto
$group1 << EOD
0.0931164 0.000337999 4.21985e-05 "1" "1"
0.101901 0.000209149 2.93932e-05 "inf" "inf"
EOD
# WCC preconditioned
$group2 << EOD
0.188484 0.000139361 2.3153e-05 "1" "1"
0.106369 0.000209149 2.93932e-05 "inf" "inf"
EOD
# WCC background
$group3 << EOD
0.158671 0.000206036 2.85671e-05 "" ""
EOD
$front_max << EOD
0.0255673 0.358343
0.0931164 0.000337999
0.101901 0.000209149
0.158671 0.000206036
0.188484 0.000139361
EOD
$front_rms << EOD
0.0255673 0.067763
0.0931164 4.21985e-05
0.101901 2.93932e-05
0.158671 2.85671e-05
0.188484 2.3153e-05
EOD

if (strstrt(GPVAL_TERMINALS, "pngcairo") > 0) {
  set terminal pngcairo size 1752,650 font ",11"
} else {
  set terminal png size 1752,650
}
set termoption noenhanced
set output "doc/study/torus_pull_60k-t2.png"
set multiplot layout 1,2 margins 0.05137, 0.8562, 0.1077, 0.9154 spacing 0.06279 title "torus_pull_60k: 64095 unknowns, 10 steps, 2 thread(s); error against the exact corotational run"
set logscale y
set format y "%.0e"
set grid
set key at screen 0.8647, screen 0.9154 left top vertical Left reverse
set xlabel "seconds per step"
set xrange [0:0.365155]
set arrow 1 from 0.338107, graph 0 to 0.338107, graph 1 nohead dashtype 2 linewidth 2 linecolor rgb "black"
set label 1 "corotational (error 0)" at 0.338107, graph 0.5 center rotate by 90 offset -1.2, 0
set ylabel "worst vertex error over the largest displacement (max over steps)"
plot $front_max using 1:2 with lines linewidth 2 linecolor rgb "gray40" title "Pareto front", \
     $group0 using 1:2 with points pointtype 5 pointsize 1.6 linecolor rgb "#9400d3" title "WCC partial", \
     $group0 using 1:2:4 with labels left offset 0.8, 0.7 textcolor rgb "#9400d3" notitle, \
     $group1 using 1:2 with points pointtype 7 pointsize 1.6 linecolor rgb "#009e73" title "WCC auto", \
     $group1 using 1:2:4 with labels left offset 0.8, -0.7 textcolor rgb "#009e73" notitle, \
     $group2 using 1:2 with points pointtype 9 pointsize 1.6 linecolor rgb "#56b4e9" title "WCC preconditioned", \
     $group2 using 1:2:4 with labels right offset -0.8, 0.7 textcolor rgb "#56b4e9" notitle, \
     $group3 using 1:2 with points pointtype 11 pointsize 1.6 linecolor rgb "#e69f00" title "WCC background", \
     $group3 using 1:2:4 with labels right offset -0.8, -0.7 textcolor rgb "#e69f00" notitle
unset key
set ylabel "RMS error over the largest displacement (max over steps)"
plot $front_rms using 1:2 with lines linewidth 2 linecolor rgb "gray40" title "Pareto front", \
     $group0 using 1:3 with points pointtype 5 pointsize 1.6 linecolor rgb "#9400d3" title "WCC partial", \
     $group0 using 1:3:5 with labels left offset 0.8, 0.7 textcolor rgb "#9400d3" notitle, \
     $group1 using 1:3 with points pointtype 7 pointsize 1.6 linecolor rgb "#009e73" title "WCC auto", \
     $group1 using 1:3:5 with labels left offset 0.8, -0.7 textcolor rgb "#009e73" notitle, \
     $group2 using 1:3 with points pointtype 9 pointsize 1.6 linecolor rgb "#56b4e9" title "WCC preconditioned", \
     $group2 using 1:3:5 with labels right offset -0.8, 0.7 textcolor rgb "#56b4e9" notitle, \
     $group3 using 1:3 with points pointtype 11 pointsize 1.6 linecolor rgb "#e69f00" title "WCC background", \
     $group3 using 1:3:5 with labels right offset -0.8, -0.7 textcolor rgb "#e69f00" notitle
unset multiplot
