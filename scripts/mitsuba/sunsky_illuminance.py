"""Mitsuba 3's `sunsky` (Hosek-Wilkie sky and sun) at one turbidity and sun elevation: the
sun's direct normal illuminance (its disk integrated) and the sky's illuminance on a
horizontal plane, in lux, as JSON. Mitsuba's RGB is radiance over the CIE y-bar integral
(106.857), so luminance = 683 * 106.857 * Y(rgb).

    python sunsky_illuminance.py TURBIDITY ELEVATION_DEG ALBEDO
"""
import json
import math
import sys

import mitsuba as mi
import numpy as np

mi.set_variant("scalar_rgb")
Y_INTEGRAL = 106.856895
LUMINANCE = np.array([0.2126, 0.7152, 0.0722])

turbidity, elevation, albedo = (float(a) for a in sys.argv[1:4])
e = math.radians(elevation)
sun = np.array([math.cos(e), 0.0, math.sin(e)])  # Mitsuba's sunsky: z up


def emitter(sun_scale, sky_scale):
    return mi.load_dict({"type": "sunsky", "sun_direction": list(sun), "turbidity": turbidity,
                         "albedo": albedo, "sun_scale": sun_scale, "sky_scale": sky_scale})


def radiance(em, d):
    si = mi.SurfaceInteraction3f()
    si.wi = mi.Vector3f(*(-d))
    return np.array(em.eval(si)) * Y_INTEGRAL


# The sun: a 0.6-degree square around its centre on a 40 x 40 grid (its disk is 0.536 across).
disk = emitter(1.0, 0.0)
u, v = np.array([-math.sin(e), 0.0, math.cos(e)]), np.array([0.0, 1.0, 0.0])
r, n = math.radians(0.3), 40
sun_rgb = np.zeros(3)
for i in range(n):
    for j in range(n):
        d = sun + ((i + 0.5) / n * 2 - 1) * r * u + ((j + 0.5) / n * 2 - 1) * r * v
        sun_rgb += radiance(disk, d / np.linalg.norm(d)) * (2 * r / n) ** 2

# The sky on a horizontal plane: midpoint rule over 90 x 360 cells of the upper hemisphere.
sky = emitter(0.0, 1.0)
rows, cols = 90, 360
sky_rgb = np.zeros(3)
for i in range(rows):
    t0, t1 = math.pi / 2 * i / rows, math.pi / 2 * (i + 1) / rows
    t = 0.5 * (t0 + t1)
    band = 0.5 * (math.sin(t1) ** 2 - math.sin(t0) ** 2) * 2 * math.pi / cols
    for j in range(cols):
        p = 2 * math.pi * (j + 0.5) / cols
        d = np.array([math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), math.cos(t)])
        sky_rgb += radiance(sky, d) * band

print(json.dumps({
    "sun_direct_normal_lux": 683 * float(sun_rgb @ LUMINANCE),
    "sky_horizontal_lux": 683 * float(sky_rgb @ LUMINANCE),
}))
