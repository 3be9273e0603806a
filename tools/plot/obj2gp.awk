# OBJ (v / f lines; f a/b/c forms too) to gnuplot polygons: each face's corners, the first again,
# then a blank line (splot ... with polygons).
$1 == "v" { n++; x[n] = $2; y[n] = $3; z[n] = $4; next }
$1 == "f" {
    for (i = 2; i <= NF; i++) { split($i, p, "/"); k = p[1] + 0; print x[k], y[k], z[k] }
    split($2, p, "/"); k = p[1] + 0; print x[k], y[k], z[k]
    print ""
}
