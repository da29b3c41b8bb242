#!/usr/bin/env python3
"""Render the chip of a cutting run from a dump_sph file (columns id type x y z temperature ...)
with the OVITO Python module's software ray tracer (Tachyon; no display needed): workpiece
particles coloured by temperature, tool particles grey, seen obliquely from the free side.
Usage: render_chip.py DUMP PNG [--crop XMIN] [--trange TLO THI]   (python from tools/python-deps.sh --print-python;
OVITO renders through Vulkan: on a machine without a GPU install the Debian package mesa-vulkan-drivers)
--crop: only particles with x >= XMIN (m), the region around the tool."""
import sys

from ovito.io import import_file
from ovito.modifiers import ColorCodingModifier, ExpressionSelectionModifier, DeleteSelectedModifier, \
    AssignColorModifier, ComputePropertyModifier
from ovito.vis import Viewport, TachyonRenderer


def main(dump, png, xmin=None, trange=(300.0, 1400.0)):
    pipe = import_file(dump)
    # particle radius: half the spacing (ids 1 and 2 are neighbours along x in the examples)
    p0 = pipe.source.data.particles
    import numpy as np
    order = np.argsort(np.asarray(p0.identifiers))
    pos = np.asarray(p0.positions)
    dx = abs(pos[order[1], 0] - pos[order[0], 0])
    pipe.modifiers.append(ComputePropertyModifier(output_property="Radius", expressions=[str(0.5 * dx)]))
    if xmin is not None:
        pipe.modifiers.append(ExpressionSelectionModifier(expression=f"Position.X < {xmin}"))
        pipe.modifiers.append(DeleteSelectedModifier())
    # cut-away view: the tool particles in front of the workpiece's mid-plane are left out
    zmid = 0.5 * (pos[:, 2].min() + pos[:, 2].max())
    pipe.modifiers.append(ExpressionSelectionModifier(expression=f"ParticleType == 2 && Position.Z > {zmid}"))
    pipe.modifiers.append(DeleteSelectedModifier())
    pipe.modifiers.append(ColorCodingModifier(property="temperature", start_value=trange[0], end_value=trange[1],
                                              gradient=ColorCodingModifier.Jet()))
    pipe.modifiers.append(ExpressionSelectionModifier(expression="ParticleType == 2"))
    pipe.modifiers.append(AssignColorModifier(color=(0.55, 0.55, 0.6)))
    pipe.modifiers.append(ExpressionSelectionModifier(expression="0"))    # clear the selection
    data = pipe.compute()
    data.cell.vis.enabled = False
    pipe.add_to_scene()
    vp = Viewport(type=Viewport.Type.Perspective, camera_dir=(-0.45, -0.3, -1.0), camera_up=(0.0, 1.0, 0.0))
    vp.zoom_all()
    vp.render_image(filename=png, size=(1200, 800), background=(1.0, 1.0, 1.0), renderer=TachyonRenderer())
    print(f"{png}: {data.particles.count} particles")


if __name__ == "__main__":
    xmin = None
    if "--crop" in sys.argv:
        k = sys.argv.index("--crop")
        xmin = float(sys.argv[k + 1])
        del sys.argv[k:k + 2]
    trange = (300.0, 1400.0)
    if "--trange" in sys.argv:
        k = sys.argv.index("--trange")
        trange = (float(sys.argv[k + 1]), float(sys.argv[k + 2]))
        del sys.argv[k:k + 3]
    main(sys.argv[1], sys.argv[2], xmin, trange)
