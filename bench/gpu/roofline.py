#!/usr/bin/env python3
"""Roofline of the 3D cutting step's kernels on one H100 (issue 26): each kernel's FP64 rate
against its arithmetic intensity, per DRAM byte and per L1 byte, beside the H100's limits.

The kernel times are the latest measured (bench/gpu/RESULTS.md, "Where the 3D step goes now" and
"The first half on staged rows": kp_timer, each kernel synchronised, the periodic slab of
4,239,104 particles on an H100, 2026-11-27); the
operations and bytes per particle are counts from the code and the Nsight Compute profile of the
pair kernel ("The mechanical step"), not measurements: they place a kernel within a factor of
about two. Writes the table (markdown) to stdout and the figure as SVG (no plotting library
needed):

    python3 bench/gpu/roofline.py [bench/gpu/roofline.svg]
"""
import math
import sys

# the H100 SXM's limits: HBM3 bandwidth, L1 bandwidth (132 SMs x 128 bytes a clock x 1.98 GHz),
# FP64 without tensor cores
DRAM_BW = 3.35e12
L1_BW = 132 * 128 * 1.98e9
FP64 = 34e12
PARTICLES = 4239104

# kernel, ms per call, FP64 operations a particle, DRAM bytes a particle, L1 bytes a particle,
# where the counts come from
KERNELS = [
    ("pair:neigh_pass", 13.27, 57 * 250, 1000, 100 * (4 + 32) + 57 * 128,
     "57 pairs x 250 operations; DRAM from Nsight (155 GB/s at 1 M); L1: 100 list entries (index, "
     "position and type), 57 rows of 128 bytes"),
    ("heat:exchange", 27.35, 100 * 30, 700, 100 * (4 + 48 + 16),
     "100 list entries: the heat row (48 bytes) and a pair of weights; about 30 operations each"),
    ("heat:weights", 19.89, 100 * 40 + 200, 600, 100 * (4 + 48),
     "100 list entries: the moments (about 40 operations each) and a 4x4 solve"),
    ("sph:initial_integrate_staged", 3.91, 500, 504 + 504 + 192 + 72 + 72, 0,
     "the state row read and written whole (staged), x, v, f read and written, the pair's packed row "
     "(192 bytes); the predictor and the radial return"),
    ("sph:final_integrate", 3.15, 500, 504 + 300 + 72 + 24, 0,
     "the state row, the corrector and the radial return, the dt reduction"),
]


def rows():
    out = []
    for name, ms, flops, dram, l1, note in KERNELS:
        t = ms * 1e-3 / PARTICLES                      # seconds a particle
        rate = flops / t                               # FP64 operations a second
        out.append(dict(name=name, ms=ms, ns=t * 1e9, rate=rate, ai_dram=flops / dram,
                        ai_l1=flops / l1 if l1 else None, dram_bw=dram / t, l1_bw=l1 / t if l1 else None,
                        roof_dram=min(FP64, DRAM_BW * flops / dram),
                        roof_l1=min(FP64, L1_BW * flops / l1) if l1 else None, note=note))
    return out


def table(rs):
    print("| kernel | ms a call | ns a particle | FP64 rate | of FP64 peak | DRAM | of its DRAM roof | L1 | of its L1 roof |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in rs:
        l1 = f"{r['l1_bw'] / 1e12:.1f} TB/s" if r["l1_bw"] else "-"
        l1r = f"{100 * r['rate'] / r['roof_l1']:.0f} %" if r["roof_l1"] else "-"
        print(f"| `{r['name']}` | {r['ms']:.2f} | {r['ns']:.2f} | {r['rate'] / 1e12:.2f} TFLOP/s | "
              f"{100 * r['rate'] / FP64:.0f} % | {r['dram_bw'] / 1e12:.2f} TB/s | "
              f"{100 * r['rate'] / r['roof_dram']:.0f} % | {l1} | {l1r} |")


def svg(rs, path):
    W, H, L, B = 720, 460, 70, 50                      # size, left and bottom margins
    x0, x1, y0, y1 = -1.0, 2.0, 10.5, 14.0             # log10 axes: intensity (FLOP/byte), rate (FLOP/s)

    def px(ai):
        return L + (math.log10(ai) - x0) / (x1 - x0) * (W - L - 20)

    def py(rate):
        return H - B - (math.log10(rate) - y0) / (y1 - y0) * (H - B - 20)

    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" font-family="sans-serif" font-size="12">',
           f'<rect width="{W}" height="{H}" fill="white"/>']
    for e in range(int(math.ceil(x0)), int(x1) + 1):
        out.append(f'<line x1="{px(10 ** e):.1f}" y1="20" x2="{px(10 ** e):.1f}" y2="{H - B}" stroke="#ddd"/>')
        out.append(f'<text x="{px(10 ** e):.1f}" y="{H - B + 16}" text-anchor="middle">1e{e}</text>')
    for e in range(int(math.ceil(y0)), int(y1) + 1):
        out.append(f'<line x1="{L}" y1="{py(10 ** e):.1f}" x2="{W - 20}" y2="{py(10 ** e):.1f}" stroke="#ddd"/>')
        out.append(f'<text x="{L - 6}" y="{py(10 ** e) + 4:.1f}" text-anchor="end">1e{e}</text>')
    out.append(f'<text x="{(L + W) / 2}" y="{H - 12}" text-anchor="middle">FP64 operations per byte</text>')
    out.append(f'<text x="16" y="{H / 2}" transform="rotate(-90 16 {H / 2})" text-anchor="middle">FP64 operations per second</text>')
    for bw, name, colour in ((DRAM_BW, "HBM3 3.35 TB/s", "#c33"), (L1_BW, "L1 33 TB/s", "#36c")):
        pts = []
        for i in range(61):
            ai = 10 ** (x0 + (x1 - x0) * i / 60)
            pts.append(f"{px(ai):.1f},{py(max(10 ** y0, min(FP64, bw * ai))):.1f}")
        out.append(f'<polyline points="{" ".join(pts)}" fill="none" stroke="{colour}" stroke-width="2"/>')
        ai_lab = 10 ** (x0 + 0.02)
        out.append(f'<text x="{px(ai_lab):.1f}" y="{py(bw * ai_lab) - 10:.1f}" fill="{colour}">{name}</text>')
    out.append(f'<text x="{W - 24}" y="{py(FP64) - 6:.1f}" text-anchor="end">FP64 34 TFLOP/s</text>')
    for k, r in enumerate(rs):
        for ai, colour in ((r["ai_dram"], "#c33"), (r["ai_l1"], "#36c")):
            if ai:
                out.append(f'<circle cx="{px(ai):.1f}" cy="{py(r["rate"]):.1f}" r="5" fill="{colour}"/>')
        ai = r["ai_dram"]
        out.append(f'<text x="{px(ai) + 8:.1f}" y="{py(r["rate"]) + 4 + 12 * (k % 2):.1f}">{r["name"]}</text>')
    out.append(f'<text x="{W - 24}" y="{H - B - 24}" text-anchor="end">each kernel twice: red per DRAM byte, blue per L1 byte</text>')
    out.append(f'<text x="{W - 24}" y="{H - B - 10}" text-anchor="end">H100, 3D slab of 4.24 M particles; operations and bytes counted, not measured</text>')
    out.append('</svg>')
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


if __name__ == "__main__":
    rs = rows()
    table(rs)
    svg(rs, sys.argv[1] if len(sys.argv) > 1 else "roofline.svg")
