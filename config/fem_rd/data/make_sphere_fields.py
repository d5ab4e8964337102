#!/usr/bin/env python3
"""Writes sphere_fields.vtp, the input of config/fem_rd/rate_from_mesh_fields.yaml: a level-3
icosphere of radius 30 with the point arrays a config's fem_rd.mesh_fields may read:
  rate        0.05 at the south pole to 0.4 at the north pole (linear in z)
  tx, ty, tz  the parallels' direction (-y, x, 0), unit length
Usage: config/fem_rd/data/make_sphere_fields.py   (rerun after changing it; the output is committed)"""
import math
import os

RADIUS = 30.0
LEVEL = 3


def icosphere(level):
    t = (1 + 5 ** 0.5) / 2
    points = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
              (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
             (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
             (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    points = [normalised(p) for p in points]
    for _ in range(level):
        middle = {}

        def midpoint(a, b):
            key = (min(a, b), max(a, b))
            if key not in middle:
                middle[key] = len(points)
                points.append(normalised([(u + v) / 2 for u, v in zip(points[a], points[b])]))
            return middle[key]

        refined = []
        for a, b, c in faces:
            ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
            refined += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = refined
    return [[RADIUS * u for u in p] for p in points], faces


def normalised(p):
    n = math.sqrt(sum(u * u for u in p))
    return [u / n for u in p]


def main():
    points, faces = icosphere(LEVEL)
    rate = [0.05 + 0.35 * (z / RADIUS + 1) / 2 for _, _, z in points]
    direction = []
    for x, y, _ in points:
        n = math.hypot(x, y)
        direction.append((-y / n, x / n, 0.0) if n > 0 else (1.0, 0.0, 0.0))
    arrays = [("rate", rate)] + [(name, [d[k] for d in direction])
                                 for k, name in enumerate(("tx", "ty", "tz"))]
    lines = ['<?xml version="1.0"?>', '<VTKFile type="PolyData" version="0.1">', "<PolyData>",
             '<Piece NumberOfPoints="%d" NumberOfPolys="%d">' % (len(points), len(faces)),
             "<PointData>"]
    for name, values in arrays:
        lines.append('<DataArray type="Float64" Name="%s" format="ascii">' % name)
        lines += ["%.9g" % v for v in values]
        lines.append("</DataArray>")
    lines += ["</PointData>", "<Points>",
              '<DataArray type="Float64" NumberOfComponents="3" format="ascii">']
    lines += ["%.9g %.9g %.9g" % tuple(p) for p in points]
    lines += ["</DataArray>", "</Points>", "<Polys>",
              '<DataArray type="Int32" Name="connectivity" format="ascii">']
    lines += ["%d %d %d" % f for f in faces]
    lines += ["</DataArray>", '<DataArray type="Int32" Name="offsets" format="ascii">']
    lines += [str(3 * (k + 1)) for k in range(len(faces))]
    lines += ["</DataArray>", "</Polys>", "</Piece>", "</PolyData>", "</VTKFile>"]
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "sphere_fields.vtp")
    with open(path, "w") as out:
        out.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
