set datafile separator ','
set terminal pngcairo size 900,480 font 'Sans,11'
set grid ytics
set output 'docs/accuracy-cost/effects.png'
set title 'Effects: what each costs per haptic tick (probing scene, scripted insert)'
set style data histograms
set style histogram clustered gap 1
set style fill solid 0.8 border -1
set ylabel 'microseconds per tick'
set xtics rotate by -20
set key left top
set termoption noenhanced
set yrange [0:*]
plot 'docs/accuracy-cost/effects.csv' skip 1 using 2:xtic(1) title 'mean', '' skip 1 using 3 title 'p50', '' skip 1 using 4 title 'p99'
