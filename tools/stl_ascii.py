"""One triangle of an ASCII STL file, its normal from the vertex order (right-handed): the facet
writer of the examples' tool generators (examples/milling-2d-ti6al4v/cutter.py,
examples/fsw-3d-aluminium/tool.py)."""
import math


def facet(out, a, b, c):
    u = [b[k] - a[k] for k in range(3)]
    v = [c[k] - a[k] for k in range(3)]
    n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
    ln = math.sqrt(sum(x * x for x in n)) or 1.0
    out.write("  facet normal %.9e %.9e %.9e\n    outer loop\n" % tuple(x / ln for x in n))
    for q in (a, b, c):
        out.write("      vertex %.17g %.17g %.17g\n" % tuple(q))
    out.write("    endloop\n  endfacet\n")
