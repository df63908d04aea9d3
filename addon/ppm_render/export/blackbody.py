"""The colour of Cycles' Blackbody node for a temperature in kelvin.

Cycles evaluates a piecewise fit of the black body's colour in linear Rec.709, normalised to a
luminance of about 1 (so a temperature changes a light's hue, not its power), converts it to the
scene linear (working) space and clamps negative channels (out of gamut) to zero. The Cycles sources
shipped with Blender 3.4, 4.2, 4.5, 5.0 and 5.2 (kernel/tables.h `blackbody_table_r/g/b`,
svm/math_util.h `svm_math_blackbody_color_rec709`, svm/blackbody.h, and the host's folding of an
unlinked Temperature, scene/shader_nodes.cpp `BlackbodyNode::constant_fold`) hold the same fit, bounds
and clamp. Only the conversion differs: Blender 5.2's kernel converts with a matrix up to 1.6e-4 from
the one the host folds with (kernel_rec709_to_scene_linear). Renders of a Blackbody-driven Emission
in each version match these functions within 3e-5 from -100 to 20000 K (tests/blenders/nodes_compare.py,
tests/addon/test_light_blackbody.py), in 5.0's ACEScg working space too.
"""

import bpy
import mathutils

from . import wavelength

# The fit's published constants (Cycles' kernel/tables.h, Apache-2.0): per temperature interval,
# R and G are a/t + b t + c and B is the cubic ((a t + b) t + c) t + d.
INTERVAL_STARTS = (965.0, 1167.0, 1449.0, 1902.0, 3315.0, 6365.0)  # above 800 K, the first interval
RED = (
    (1.61919106e03, -2.05010916e-03, 5.02995757e00),
    (2.48845471e03, -1.11330907e-03, 3.22621544e00),
    (3.34143193e03, -4.86551192e-04, 1.76486769e00),
    (4.09461742e03, -1.27446582e-04, 7.25731635e-01),
    (4.67028036e03, 2.91258199e-05, 1.26703442e-01),
    (4.59509185e03, 2.87495649e-05, 1.50345020e-01),
    (3.78717450e03, 9.35907826e-06, 3.99075871e-01),
)
GREEN = (
    (-4.88999748e02, 6.04330754e-04, -7.55807526e-02),
    (-7.55994277e02, 3.16730098e-04, 4.78306139e-01),
    (-1.02363977e03, 1.20223470e-04, 9.36662319e-01),
    (-1.26571316e03, 4.87340896e-06, 1.27054498e00),
    (-1.42529332e03, -4.01150431e-05, 1.43972784e00),
    (-1.17554822e03, -2.16378048e-05, 1.30408023e00),
    (-5.00799571e02, -4.59832026e-06, 1.09098763e00),
)
BLUE = (
    (5.96945309e-11, -4.85742887e-08, -9.70622247e-05, -4.07936148e-03),
    (2.40430366e-11, 5.55021075e-08, -1.98503712e-04, 2.89312858e-02),
    (-1.40949732e-11, 1.89878968e-07, -3.56632824e-04, 9.10767778e-02),
    (-3.61460868e-11, 2.84822009e-07, -4.93211319e-04, 1.56723440e-01),
    (-1.97075738e-11, 1.75359352e-07, -2.50542825e-04, -2.22783266e-02),
    (-1.61997957e-13, -1.64216008e-08, 3.86216271e-04, -7.38077418e-01),
    (6.72650283e-13, -2.73078809e-08, 4.24098264e-04, -7.52335691e-01),
)
# Outside 800..12000 K Cycles does not extrapolate the fit but holds these colours (the fit's
# values at the ends, from the same source), so a colder or hotter body keeps its end colour.
COLDEST, HOTTEST = 800.0, 12000.0
BELOW_COLDEST = (5.413294490189271, -0.20319390035873933, -0.0822535242887164)
HOTTEST_RGB = (0.8262954810464208, 0.9945080501520986, 1.566307710274283)


def blackbody_rec709(kelvin):
    """The fit's linear Rec.709 colour at `kelvin`, before clamping (a channel may be negative)."""
    t = float(kelvin)
    if t >= HOTTEST:
        return HOTTEST_RGB
    if t < COLDEST:
        return BELOW_COLDEST
    i = sum(t >= start for start in INTERVAL_STARTS)
    (ra, rb, rc), (ga, gb, gc), (ba, bb, bc, bd) = RED[i], GREEN[i], BLUE[i]
    return (ra / t + rb * t + rc, ga / t + gb * t + gc, ((ba * t + bb) * t + bc) * t + bd)


def blackbody_rgb(kelvin, matrix=None):
    """Cycles' Blackbody colour at `kelvin` in the scene linear space: the fit converted from Rec.709
    by `matrix` (rows; by default the host's, the identity in Blender's default working space), then
    clamped at zero as Cycles does."""
    rec709 = blackbody_rec709(kelvin)
    rows = matrix or rec709_to_scene_linear()
    return tuple(max(sum(m * c for m, c in zip(row, rec709)), 0.0) for row in rows)


def rec709_to_scene_linear():
    """The 3 x 3 matrix (rows) Blender converts linear Rec.709 to the scene linear space with."""
    columns = [mathutils.Color(axis).from_rec709_linear_to_scene_linear() for axis in ((1, 0, 0), (0, 1, 0), (0, 0, 1))]
    return [[float(columns[j][i]) for j in range(3)] for i in range(3)]


# The XYZ (D65) to linear Rec.709 constants Blender used before 5.0 (5.0 rounded them to four digits).
XYZ_TO_REC709_BEFORE_5_0 = mathutils.Matrix(((3.2404542, -1.5371385, -0.4985314),
                                             (-0.9692660, 1.8760108, 0.0415560),
                                             (0.0556434, -0.2040259, 1.0572252)))


def kernel_rec709_to_scene_linear():
    """The matrix (rows) Cycles' kernel converts the fit with. Blender 5.2's kernel goes through XYZ and the
    older constants' inverse (measured: its renders match this within 2e-6, the host's matrix only within
    4e-4); before, it used the host's matrix. 5.1 is not measured."""
    if bpy.app.version < (5, 1, 0):
        return rec709_to_scene_linear()
    product = mathutils.Matrix(wavelength.xyz_to_scene_linear()) @ XYZ_TO_REC709_BEFORE_5_0.inverted()
    return [[float(v) for v in row] for row in product]


def program_data():
    """The floats the core's Blackbody instruction reads (node_program.h kBlackbodyFit): the matrix
    (9, rows), the interval starts, the fitted range, the colours held beyond it, the coefficients."""
    fit = [*INTERVAL_STARTS, COLDEST, HOTTEST, *BELOW_COLDEST, *HOTTEST_RGB]
    for red, green, blue in zip(RED, GREEN, BLUE):
        fit += [*red, *green, *blue]
    return [v for row in kernel_rec709_to_scene_linear() for v in row] + [float(v) for v in fit]
