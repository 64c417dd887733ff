# The error-against-time study, written by warpchol-threshold-sweep: edit and
# rerun with `gnuplot THIS_FILE` from the directory the sweep ran in.
# Per configuration: seconds per step, the largest over the steps of the worst
# vertex's error max_i |x_i - x_i(ref)| and of the RMS error
# sqrt(mean_i |x_i - x_i(ref)|^2), both over max_i |x_i(ref) - X_i|; its label.

# WCC partial
$group0 << EOD
0.000196261 0.00542781 0.00244898 "0.03" "0.03"
0.000161489 0.0151035 0.00677565 "0.1" "0.1"
0.000142578 0.0261565 0.0117701 "0.3" "0.3"
0.000130997 0.0406232 0.0183263 "1" "1"
7.37922e-05 0.119057 0.0606778 "inf" "inf"
EOD
# WCC delayed_top
$group1 << EOD
0.000216561 0.000116003 2.1682e-05 "0.3" "0.3"
0.000212565 5.21885e-05 2.66912e-05 "1" "1"
0.000209059 8.59023e-05 1.88908e-05 "inf" "inf"
EOD
# WCC preconditioned
$group2 << EOD
0.000223898 0.000118866 2.24838e-05 "0.3" "0.3"
0.000214894 4.93769e-05 2.50142e-05 "1" "1"
0.000207773 8.59023e-05 1.88908e-05 "inf" "inf"
EOD
# WCC auto
$group3 << EOD
0.00018379 0.000116003 2.1682e-05 "0.3" "0.3"
0.000293335 6.84218e-05 2.35808e-05 "1" "1"
0.000159929 8.84616e-05 2.14157e-05 "inf" "inf"
EOD
# WCC background
$group4 << EOD
0.000168482 0.000101129 2.15331e-05 "" ""
EOD
# WCC target error
$group5 << EOD
0.000261894 0.00249401 0.00152406 "0.3%" "0.3%"
0.000228711 0.00947801 0.00524934 "1%" "1%"
EOD
$front_max << EOD
7.37922e-05 0.119057
0.000130997 0.0406232
0.000142578 0.0261565
0.000159929 8.84616e-05
0.000207773 8.59023e-05
0.000212565 5.21885e-05
0.000214894 4.93769e-05
EOD
$front_rms << EOD
7.37922e-05 0.0606778
0.000130997 0.0183263
0.000142578 0.0117701
0.000159929 2.14157e-05
0.000207773 1.88908e-05
EOD

if (strstrt(GPVAL_TERMINALS, "pngcairo") > 0) {
  set terminal pngcairo size 1752,650 font ",11"
} else {
  set terminal png size 1752,650
}
set termoption noenhanced
set output "doc/study/liver-t1.png"
set multiplot layout 1,2 margins 0.05137, 0.8562, 0.1077, 0.9154 spacing 0.06279 title "liver: 534 unknowns, 200 steps, 1 thread(s); error against the exact corotational run"
set logscale y
set format y "%.0e"
set grid
set key at screen 0.8647, screen 0.9154 left top vertical Left reverse
set xlabel "seconds per step"
set xrange [0:0.000316802]
set arrow 1 from 0.00026235, graph 0 to 0.00026235, graph 1 nohead dashtype 2 linewidth 2 linecolor rgb "black"
set label 1 "corotational (error 0)" at 0.00026235, graph 0.5 center rotate by 90 offset -1.2, 0
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
