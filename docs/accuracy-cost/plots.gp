set datafile separator ','
set terminal pngcairo size 900,560 font 'Sans,11'
set grid
set key left top
set output 'docs/accuracy-cost/resolution.png'
set title 'Sphere-tree resolution: what it buys (protrusion) and what it costs (time)'
set logscale x 2
set xlabel 'leaf spheres'
set ylabel 'protrusion, % of largest extent'
set y2label 'time (us per frame; build: ms)'
set y2tics
set logscale y
set logscale y2
plot 'docs/accuracy-cost/resolution.csv' skip 1 using 1:3 with linespoints lw 2 title 'worst protrusion', '' skip 1 using 1:4 with linespoints lw 2 title 'mean protrusion', '' skip 1 using 1:6 axes x1y2 with linespoints dt 2 lw 2 title 'frame p50 (us)', '' skip 1 using 1:7 axes x1y2 with linespoints dt 2 lw 2 title 'frame p99 (us)', '' skip 1 using 1:($5*1000) axes x1y2 with linespoints dt 3 lw 2 title 'build (ms)'
unset logscale
set logscale x 10
set format x '10^{%L}'
unset y2tics
unset y2label
set output 'docs/accuracy-cost/tolerance.png'
set title 'Solver tolerance: penetration allowed vs frame time'
set xlabel 'penetration tolerance (mm)'
set ylabel 'us per frame / linearisations x 10'
set logscale y
plot 'docs/accuracy-cost/tolerance.csv' skip 1 using 1:2 with linespoints lw 2 title 'frame p50 (us)', '' skip 1 using 1:3 with linespoints lw 2 title 'frame p99 (us)', '' skip 1 using 1:($4*10) with linespoints lw 2 title 'mean linearisations x 10'
unset logscale
set logscale x 2
set format x '%g'
set y2tics
set output 'docs/accuracy-cost/ripple.png'
set title 'Sliding on a flat plate: what the hand feels of the sphere bumps'
set key right center
set xlabel 'leaf spheres of the plate'
set ylabel 'normal force ripple, % (peak to peak / mean)'
set y2label 'rendered tool height ripple (mm)'
set logscale y
set logscale y2
plot 'docs/accuracy-cost/ripple.csv' skip 1 using 1:2 with linespoints lw 2 title 'force ripple %, spheres', '' skip 1 using 1:($11 > 0.01 ? $11 : 0.01) with linespoints lw 2 title 'force ripple %, clipped leaves (0.01 = none)', 7 with lines dt 2 lw 1 title 'Weber fraction for force (7 %)', '' skip 1 using 1:3 axes x1y2 with linespoints dt 3 lw 2 title 'height ripple (mm), spheres', '' skip 1 using 1:($12 > 1e-5 ? $12 : 1e-5) axes x1y2 with linespoints dt 3 lw 2 title 'height ripple (mm), clipped leaves'
