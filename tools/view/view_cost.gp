# Chart of tools/view/view_cost.sh: each stage's p50 and p99 without and with the view.
#   gnuplot -e "outdir='DIR'" view_cost.gp
set terminal pngcairo size 1000,450
set output outdir."/view_cost.png"
set datafile separator ","
set style data histograms
set style histogram clustered gap 1
set style fill solid 0.8 border -1
set ylabel "ms"
set title "Pipeline stages without and with arphys-view (one client, 30 FPS)"
set xtics rotate by -25
set key top left
plot outdir."/view_cost.csv" using 2:xtic(1) skip 1 title "p50 without", \
     "" using 3 skip 1 title "p50 with", \
     "" using 5 skip 1 title "p99 without", \
     "" using 6 skip 1 title "p99 with"
