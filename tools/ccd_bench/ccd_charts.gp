# Charts of the CCD benchmark (called by run_benchmarks.sh with summary, tunnelling, outdir).
set datafile separator ','
set terminal pngcairo size 900,600 font ',11'

# 1. Speed against accuracy: median time per query against the largest TOI error.
#    Methods that missed collisions are drawn in red.
set output outdir.'/ccd_speed_accuracy.png'
set title "CCD speed vs accuracy (bunny 5k vs bunny 5k, random screw motions)"
set logscale xy
set xlabel 'median time per query (us, log)'
set ylabel 'largest |TOI error| over the hits (fraction of the step, log)'
set format y '10^{%T}'
set grid
set key off
clamp_low(x) = (x > 1e-10 ? x : 1e-10)
plot summary every ::1 using 12:(clamp_low($10)):($5 > 0 ? 0xcc0000 : 0x0060c0) with points pt 7 ps 1.6 lc rgb variable, \
     summary every ::1 using 12:(clamp_low($10)):(stringcolumn(1).($5 > 0 ? sprintf(' (%d missed)', $5) : '')) \
       with labels offset 1,0.8 left font ',9'

# 2. Tunnelling: missed-collision rate against travel per step over thickness.
set output outdir.'/ccd_tunnelling.png'
set title "Missed collisions: a 1 cm cube flying through a 1 cm plate"
unset logscale y
set logscale x
set format y '%.1f'
set xlabel 'travel per step / (plate thickness + cube side)  (log)'
set ylabel 'missed-collision rate'
set yrange [-0.05:1.05]
set key outside right
methods = "arphys-ccd discrete-10 discrete-100 discrete-1000 fcl-naive-10 fcl-naive-100 fcl-ca-obbrss"
plot for [m in methods] tunnelling every ::1 using 1:(stringcolumn(2) eq m ? $3 : 1/0) with linespoints lw 2 title m
