#!/usr/bin/env python3
"""Write the instrument paths of parameters/flap_incision.prm, shaped as a haptic device records them.

    python3 parameters/paths/make_flap_paths.py     # rewrites flap_blade.csv, flap_jaws.csv

Samples at 500 Hz, as a haptic device gives them: the scalpel draws a U around a tongue of tissue (two
straight strokes joined by a half circle, the hinge left open towards the fixed edge),
then the grasper's jaws come down on the tongue's tip, lift it and hold. The hand's
tremor is a sum of a few sines (8-12 Hz, a tenth of a millimetre), so the files are the
same on every run; the device's readings are rounded to a micrometre, as it records them.
"""

import math
import os

RATE = 500.0  # Hz
HERE = os.path.dirname(os.path.abspath(__file__))


def tremor(t, phase):
    """A hand's physiological tremor (m): deterministic, 8-12 Hz, about 0.1 mm."""
    return 6e-5 * math.sin(2 * math.pi * 8.3 * t + phase) + 4e-5 * math.sin(2 * math.pi * 11.7 * t + 2 * phase)


def smooth(s):
    """0 to 1 with zero speed at both ends: a stroke that starts and ends at rest."""
    return s * s * (3 - 2 * s)


def u_curve(s):
    """The incision's curve, s from 0 to 1: along y = 0.03, round (0.07, 0.05), back along y = 0.07."""
    straight, radius = 0.03, 0.02
    length = 2 * straight + math.pi * radius
    d = s * length
    if d < straight:
        return 0.04 + d, 0.03
    d -= straight
    if d < math.pi * radius:
        angle = -math.pi / 2 + d / radius
        return 0.07 + radius * math.cos(angle), 0.05 + radius * math.sin(angle)
    d -= math.pi * radius
    return 0.07 - d, 0.07


def write(name, header, rows):
    with open(os.path.join(HERE, name), "w") as out:
        out.write("# " + name + ": written by make_flap_paths.py (500 Hz, positions in m, rounded to 1 um)\n")
        out.write(header + "\n")
        for row in rows:
            out.write(",".join("%.6f" % value if i > 0 else "%.4f" % value for i, value in enumerate(row)) + "\n")


def main():
    # The scalpel: its edge vertical through the 1 cm slab (z from -4 mm to 14 mm), cutting
    # from 0.10 s to 1.30 s; a little before and after it hovers in place.
    begin, end = 0.05, 1.35
    cut_begin, cut_end = 0.10, 1.30
    rows = []
    for k in range(int(round((end - begin) * RATE)) + 1):
        t = begin + k / RATE
        s = smooth(min(max((t - cut_begin) / (cut_end - cut_begin), 0.0), 1.0))
        x, y = u_curve(s)
        x += tremor(t, 0.3)
        y += tremor(t, 1.1)
        tilt = tremor(t, 2.0)  # the handle wobbles: the top end moves a little more
        rows.append((t, x, y, -0.004, x + 2 * tilt, y - tilt, 0.014))
    write("flap_blade.csv", "time,start_x,start_y,start_z,end_x,end_y,end_z", rows)

    # The jaws: come to rest on the tongue's tip at 1.40 s, lift it 3 cm and draw it
    # back 1 cm towards the hinge by 2.00 s, hold it until it is released at 2.30 s.
    begin, end = 1.35, 2.40
    tip = (0.083, 0.05, 0.01)
    rows = []
    for k in range(int(round((end - begin) * RATE)) + 1):
        t = begin + k / RATE
        s = smooth(min(max((t - 1.40) / 0.60, 0.0), 1.0))
        rows.append((t, tip[0] - 0.01 * s + tremor(t, 0.7), tip[1] + tremor(t, 1.9), tip[2] + 0.03 * s + tremor(t, 2.9)))
    write("flap_jaws.csv", "time,x,y,z", rows)


if __name__ == "__main__":
    main()
