# A strip of rendered frames: one row per run, one column per frame, the same box in every panel.
# gnuplot -e "rows='dirA dirB'; titles='A B'; frames='25 50'; box='x0 x1 z0 z1 y0 y1'; out='strip.png'" tools/plot/strip.gp
# Each dir holds frame_NNNNN.obj (romkit fom --frames, romkit run --frames).
nr = words(rows); nc = words(frames)
set terminal pngcairo size 260 * nc, 180 * nr font "sans,9"
set output out
# y (up in the scene) is drawn as gnuplot's vertical axis: using 1:3:2
set view 80, 5, 1.6
set view equal xyz
unset border; unset tics; unset key; unset colorbox
set xrange [word(box, 1):word(box, 2)]; set yrange [word(box, 3):word(box, 4)]; set zrange [word(box, 5):word(box, 6)]
set pm3d depthorder border lc rgb "#303030" lw 0.2
set multiplot layout nr, nc margins 0.02, 0.98, 0.02, 0.92 spacing 0.01, 0.06
colors = "#7aa6d6 #e3a857 #8cc084 #c47ab0"
do for [i = 1:nr] {
  do for [j = 1:nc] {
    set title sprintf("%s, frame %d", word(titles, i), word(frames, j) + 0) font "sans,9" noenhanced
    splot sprintf("< awk -f tools/plot/obj2gp.awk %s/frame_%05d.obj", word(rows, i), word(frames, j) + 0) \
          using 1:3:2 with polygons fs solid 1.0 fc rgb word(colors, i)
  }
}
unset multiplot
