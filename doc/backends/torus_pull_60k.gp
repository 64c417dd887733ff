# The error-against-time study, written by warpchol-threshold-sweep: edit and
# rerun with `gnuplot THIS_FILE` from the directory the sweep ran in.
# Per configuration: seconds per step, the largest over the steps of the worst
# vertex's error max_i |x_i - x_i(ref)| and of the RMS error
# sqrt(mean_i |x_i - x_i(ref)|^2), both over max_i |x_i(ref) - X_i|; its label.

# WCC partial
$group0 << EOD
0.438875 0.00356364 0.0010711 "0.3" "0.3"
0.403247 0.0151297 0.00385526 "1" "1"
EOD
# WCC auto
$group1 << EOD
0.209116 0.000265167 4.47644e-05 "1" "1"
0.185404 0.000209147 2.93932e-05 "inf" "inf"
EOD
# WCC preconditioned
$group2 << EOD
0.426772 0.00013936 2.31531e-05 "1" "1"
0.181761 0.000209147 2.93932e-05 "inf" "inf"
EOD
# cholmod
$group3 << EOD
0.969226 3.37329e-15 2.15488e-16 "" ""
EOD
# umfpack
$group4 << EOD
8.10425 2.6052e-15 2.12476e-16 "" ""
EOD
# eigen
$group5 << EOD
99.686 4.78912e-13 8.67984e-14 "" ""
EOD
# eigen_cholmod
$group6 << EOD
0.885972 3.37329e-15 2.15488e-16 "" ""
EOD
# trilinos_amg_cg
$group7 << EOD
0.593098 6.94192e-07 7.86692e-08 "1e-06" "1e-06"
0.316612 0.00114534 9.54056e-05 "0.001" "0.001"
EOD
# warp_preconditioned_cg
$group8 << EOD
0.556619 3.22224e-07 1.50024e-08 "1e-06" "1e-06"
0.254513 0.000209146 2.93937e-05 "0.001" "0.001"
EOD
# WCC target error
$group9 << EOD
0.440514 0.00793251 0.00221158 "1%" "1%"
EOD
$front_max << EOD
0.181761 0.000209147
0.254513 0.000209146
0.426772 0.00013936
0.556619 3.22224e-07
EOD
$front_rms << EOD
0.181761 2.93932e-05
0.426772 2.31531e-05
0.556619 1.50024e-08
EOD

if (strstrt(GPVAL_TERMINALS, "pngcairo") > 0) {
  set terminal pngcairo size 1788,650 font ",11"
} else {
  set terminal png size 1788,650
}
set termoption noenhanced
set output "doc/backends/torus_pull_60k.png"
set multiplot layout 1,2 margins 0.05034, 0.8389, 0.1077, 0.9154 spacing 0.06152 title "torus_pull_60k: 64095 unknowns, 10 steps, 1 thread(s); error against the exact corotational run"
set logscale y
set format y "%.0e"
set grid
set key at screen 0.8473, screen 0.9154 left top vertical Left reverse
set xlabel "seconds per step"
set logscale x
set xrange [0.127233:139.56]
set arrow 1 from 0.864278, graph 0 to 0.864278, graph 1 nohead dashtype 2 linewidth 2 linecolor rgb "black"
set label 1 "corotational (error 0)" at 0.864278, graph 0.5 center rotate by 90 offset -1.2, 0
set ylabel "worst vertex error over the largest displacement (max over steps)"
plot $front_max using 1:2 with lines linewidth 2 linecolor rgb "gray40" title "Pareto front", \
     $group0 using 1:2 with points pointtype 5 pointsize 1.6 linecolor rgb "#9400d3" title "WCC partial", \
     $group0 using 1:2:4 with labels left offset 0.8, 0.7 textcolor rgb "#9400d3" notitle, \
     $group1 using 1:2 with points pointtype 7 pointsize 1.6 linecolor rgb "#009e73" title "WCC auto", \
     $group1 using 1:2:4 with labels left offset 0.8, -0.7 textcolor rgb "#009e73" notitle, \
     $group2 using 1:2 with points pointtype 9 pointsize 1.6 linecolor rgb "#56b4e9" title "WCC preconditioned", \
     $group2 using 1:2:4 with labels right offset -0.8, 0.7 textcolor rgb "#56b4e9" notitle, \
     $group3 using 1:2 with points pointtype 11 pointsize 1.6 linecolor rgb "#e69f00" title "cholmod", \
     $group3 using 1:2:4 with labels right offset -0.8, -0.7 textcolor rgb "#e69f00" notitle, \
     $group4 using 1:2 with points pointtype 13 pointsize 1.6 linecolor rgb "#f0e442" title "umfpack", \
     $group4 using 1:2:4 with labels left offset 0.8, 0.7 textcolor rgb "#f0e442" notitle, \
     $group5 using 1:2 with points pointtype 15 pointsize 1.6 linecolor rgb "#0072b2" title "eigen", \
     $group5 using 1:2:4 with labels left offset 0.8, -0.7 textcolor rgb "#0072b2" notitle, \
     $group6 using 1:2 with points pointtype 4 pointsize 1.6 linecolor rgb "#e51e10" title "eigen_cholmod", \
     $group6 using 1:2:4 with labels right offset -0.8, 0.7 textcolor rgb "#e51e10" notitle, \
     $group7 using 1:2 with points pointtype 6 pointsize 1.6 linecolor rgb "#000000" title "trilinos_amg_cg", \
     $group7 using 1:2:4 with labels right offset -0.8, -0.7 textcolor rgb "#000000" notitle, \
     $group8 using 1:2 with points pointtype 8 pointsize 1.6 linecolor rgb "#a0522d" title "warp_preconditioned_cg", \
     $group8 using 1:2:4 with labels left offset 0.8, 0.7 textcolor rgb "#a0522d" notitle, \
     $group9 using 1:2 with points pointtype 10 pointsize 1.6 linecolor rgb "#ff69b4" title "WCC target error", \
     $group9 using 1:2:4 with labels left offset 0.8, -0.7 textcolor rgb "#ff69b4" notitle
unset key
set ylabel "RMS error over the largest displacement (max over steps)"
plot $front_rms using 1:2 with lines linewidth 2 linecolor rgb "gray40" title "Pareto front", \
     $group0 using 1:3 with points pointtype 5 pointsize 1.6 linecolor rgb "#9400d3" title "WCC partial", \
     $group0 using 1:3:5 with labels left offset 0.8, 0.7 textcolor rgb "#9400d3" notitle, \
     $group1 using 1:3 with points pointtype 7 pointsize 1.6 linecolor rgb "#009e73" title "WCC auto", \
     $group1 using 1:3:5 with labels left offset 0.8, -0.7 textcolor rgb "#009e73" notitle, \
     $group2 using 1:3 with points pointtype 9 pointsize 1.6 linecolor rgb "#56b4e9" title "WCC preconditioned", \
     $group2 using 1:3:5 with labels right offset -0.8, 0.7 textcolor rgb "#56b4e9" notitle, \
     $group3 using 1:3 with points pointtype 11 pointsize 1.6 linecolor rgb "#e69f00" title "cholmod", \
     $group3 using 1:3:5 with labels right offset -0.8, -0.7 textcolor rgb "#e69f00" notitle, \
     $group4 using 1:3 with points pointtype 13 pointsize 1.6 linecolor rgb "#f0e442" title "umfpack", \
     $group4 using 1:3:5 with labels left offset 0.8, 0.7 textcolor rgb "#f0e442" notitle, \
     $group5 using 1:3 with points pointtype 15 pointsize 1.6 linecolor rgb "#0072b2" title "eigen", \
     $group5 using 1:3:5 with labels left offset 0.8, -0.7 textcolor rgb "#0072b2" notitle, \
     $group6 using 1:3 with points pointtype 4 pointsize 1.6 linecolor rgb "#e51e10" title "eigen_cholmod", \
     $group6 using 1:3:5 with labels right offset -0.8, 0.7 textcolor rgb "#e51e10" notitle, \
     $group7 using 1:3 with points pointtype 6 pointsize 1.6 linecolor rgb "#000000" title "trilinos_amg_cg", \
     $group7 using 1:3:5 with labels right offset -0.8, -0.7 textcolor rgb "#000000" notitle, \
     $group8 using 1:3 with points pointtype 8 pointsize 1.6 linecolor rgb "#a0522d" title "warp_preconditioned_cg", \
     $group8 using 1:3:5 with labels left offset 0.8, 0.7 textcolor rgb "#a0522d" notitle, \
     $group9 using 1:3 with points pointtype 10 pointsize 1.6 linecolor rgb "#ff69b4" title "WCC target error", \
     $group9 using 1:3:5 with labels left offset 0.8, -0.7 textcolor rgb "#ff69b4" notitle
unset multiplot
