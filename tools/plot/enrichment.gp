# The adaptive subspace's enrichment on the surface: one column per frame; the top row the oracle's
# error G (log10, in its thresholds' units: above 0 the oracle enriches), the bottom row the vertices
# enriched when the step's solve ended. Data: tools/plot/fields_obj.py (romkit adaptive --frames,
# --snapshots, --fields).
# gnuplot -e "dir='D'; frames='3 4 6 9'; box='x0 x1 z0 z1 y0 y1'; out='enrichment.png'" tools/plot/enrichment.gp
nc = words(frames)
set terminal pngcairo size 260 * nc, 400 font "sans,9"
set output out
set view 35, 20, 1.6
set view equal xyz
unset border; unset tics; unset key
set xrange [word(box, 1):word(box, 2)]; set yrange [word(box, 3):word(box, 4)]; set zrange [word(box, 5):word(box, 6)]
set pm3d depthorder border lc rgb "#303030" lw 0.1
set multiplot layout 2, nc margins 0.02, 0.90, 0.02, 0.92 spacing 0.01, 0.08
data(f, c) = sprintf("< python3 tools/plot/fields_obj.py %s/frame_%05d.obj %s/S.npy %s/F.npy %d %d", dir, f, dir, dir, f, c)
set palette defined (-3 "#2c5aa0", 0 "#f0f0f0", 3 "#c0392b")
set cbrange [-3:3]
do for [j = 1:nc] {
  f = word(frames, j) + 0
  set title sprintf("frame %d: log10 G", f) font "sans,9"
  if (j == nc) { set colorbox user origin 0.92, 0.55 size 0.015, 0.33; set cbtics 1 font "sans,8" } else { unset colorbox }
  splot data(f, 2) using 1:3:2:4 with pm3d
}
set palette defined (0 "#d0d0d0", 1 "#e3a857")
set cbrange [0:1]
do for [j = 1:nc] {
  f = word(frames, j) + 0
  set title sprintf("frame %d: enriched", f) font "sans,9"
  unset colorbox
  splot data(f, 1) using 1:3:2:4 with pm3d
}
unset multiplot
