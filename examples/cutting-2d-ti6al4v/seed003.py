"""The seed-003 cutting case's reference figures (Afrasiabi, Klippel, Roethlin, Wegener, "Smoothed
particle hydrodynamics simulation of orthogonal cutting with enhanced thermal modeling", Appl. Sci.
11 (2021) 1020, doi:10.3390/app11031020),
in one place for the example's scripts and bench/ (steady.py, plot.py, bench/cutting/*.py,
bench/pareto/run.sh, bench/cutting/sensitivity.sh), and the steady-state window they all use.
The geometry and speed must match in.cutting (variables h, rn, H and vc)."""

# experiment, seed 003 Fig. 6: cutting and thrust force per mm of width [N/mm]
EXP_FC, EXP_FT = 157.5, 104.2
EXP = (EXP_FC, EXP_FT)
# the paper's SPH results over 2 mm at 41 across [N/mm]
PAPER = {"SPH reference thermal model, mu 0.35": (177.8, 92.9),
         "SPH proposed thermal model, mu 0.35": (180.3, 89.0),
         "SPH proposed thermal model, mu 0.65": (185.0, 103.5)}
SPH_FC, SPH_FT = PAPER["SPH proposed thermal model, mu 0.35"]
# low-speed case (sec. 5.2.2, vc 20 m/min, 0.3 mm of cut): rake-face temperature [K]
LOWSPEED_T_EXP = 680.0      # measured, about
LOWSPEED_T_PAPER = 744.0    # the paper's SPH
# in.cutting's geometry and speed (its defaults)
UNCUT = 0.1e-3              # uncut chip thickness h [m] (-var h)
EDGE_RADIUS = 28.7e-6       # cutting-edge radius rn [m] (-var rn): the measured edge of test V0061 (Klippel et
                            # al., Int J Adv Manuf Technol 135 (2024) 2871, doi:10.1007/s00170-024-14597-2);
                            # the paper's Table 1: 2.8e-6
HEIGHT = 0.3e-3             # the paper's workpiece height [m] (height(UNCUT, EDGE_RADIUS))
VC = 318.5                  # cutting speed [m/min]
RHO0 = 4430.0               # Ti6Al4V reference density [kg/m^3]
STEADY_FROM = 0.1           # steady state: after this fraction of the cut (as seed 003)


def height(h=UNCUT, rn=EDGE_RADIUS, H=0.0):
    """workpiece height [m] of in.cutting: -var H, or with H 0 (its default) max(3 h, h + 3 rn)"""
    return H if H > 0 else max(3.0 * h, h + 3.0 * rn)


def spacing(ny, h=UNCUT, rn=EDGE_RADIUS, H=0.0):
    """particle spacing [m] of in.cutting at ny particles across the height"""
    return height(h, rn, H) / (ny - 1)


def block_error(values, nblock=5):
    """standard error of the mean from nblock consecutive block means (the samples of a cut are
    correlated over many steps, and the chip of Ti6Al4V is serrated: block means are closer to
    independent); nan with fewer than 2 samples a block"""
    m = len(values) // nblock
    if m < 2:
        return float("nan")
    means = [sum(values[b * m:(b + 1) * m]) / m for b in range(nblock)]
    mu = sum(means) / nblock
    return (sum((x - mu) ** 2 for x in means) / (nblock - 1) / nblock) ** 0.5


def steady_rows(rows):
    """the rows of forces.dat (steady.read_rows) in the steady state: cut length >= 10 % of the
    run's; returns (the run's cut length [mm], the selected rows)"""
    lmax = max(r[1] for r in rows)
    return lmax, [r for r in rows if r[1] >= STEADY_FROM * lmax and r[1] > 0.0]


if __name__ == "__main__":    # for shell scripts: python3 seed003.py spacing NY [h rn H] | vc
    import sys
    print({"spacing": lambda: spacing(int(sys.argv[2]), *map(float, sys.argv[3:6])),
           "vc": lambda: VC}[sys.argv[1]]())
