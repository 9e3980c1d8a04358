"""ASCII STL meshes for stock LIGGGHTS walls (`fix mesh/surface`), used to
build stock peers of our walls: a flat annulus is the silo bottom with its
orifice as a mesh."""

import math


def annulus_triangles(inner_radius, outer_radius, segments=64, height=0.0):
    """Triangles of the flat annulus inner_radius < r < outer_radius in the
    plane z = height, centred on the z axis: `segments` trapezoids, two
    triangles each, with their normals along +z (counter-clockwise seen from
    above). The hole is the regular polygon with `segments` vertices on the
    circle of radius inner_radius (0: a full disc, its centre a vertex)."""
    if not 0.0 <= inner_radius < outer_radius:
        raise ValueError("need 0 <= inner_radius < outer_radius")
    triangles = []
    for k in range(segments):
        a0 = 2.0 * math.pi * k / segments
        a1 = 2.0 * math.pi * (k + 1) / segments

        def point(radius, angle):
            return (radius * math.cos(angle), radius * math.sin(angle), height)

        inner0, inner1 = point(inner_radius, a0), point(inner_radius, a1)
        outer0, outer1 = point(outer_radius, a0), point(outer_radius, a1)
        triangles.append((inner0, outer0, outer1))
        if inner_radius > 0.0:
            triangles.append((inner0, outer1, inner1))
    return triangles


def write_stl(path, triangles, name="silokit"):
    """Writes triangles (three (x, y, z) vertices each) as ASCII STL."""
    with open(path, "w") as handle:
        handle.write(f"solid {name}\n")
        for a, b, c in triangles:
            u = [b[i] - a[i] for i in range(3)]
            v = [c[i] - a[i] for i in range(3)]
            n = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
            length = math.sqrt(sum(x * x for x in n)) or 1.0
            handle.write(" facet normal {:.9g} {:.9g} {:.9g}\n  outer loop\n".format(*(x / length for x in n)))
            for vertex in (a, b, c):
                handle.write("   vertex {:.12g} {:.12g} {:.12g}\n".format(*vertex))
            handle.write("  endloop\n endfacet\n")
        handle.write(f"endsolid {name}\n")
