#!/usr/bin/env python3
"""Writes the seed corpus of the fuzz targets (fuzz/corpus/<target>/): small valid PCD and
PLY files of every storage kind and a few edge cases for fuzz_cloud_file, and inputs in
fuzz_filters' layout (see fuzz/fuzz_filters.cpp) for fuzz_filters. Deterministic: running
it again rewrites the same files. Inputs that once crashed a target are added by hand
next to these seeds (named crash-*) and are not touched here."""
import math
import os
import random
import struct

HERE = os.path.dirname(os.path.abspath(__file__))


def write(target, name, data):
    folder = os.path.join(HERE, "corpus", target)
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, name), "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())


def sphere(n, seed, noise=0.01):
    rng = random.Random(seed)
    points = []
    for _ in range(n):
        v = [rng.gauss(0, 1) for _ in range(3)]
        r = math.sqrt(sum(c * c for c in v)) or 1.0
        s = (1.0 + noise * rng.gauss(0, 1)) / r
        points.append([c * s for c in v])
    return points


def pcd_header(fields, sizes, types, counts, width, height, data):
    return ("# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\n"
            f"FIELDS {' '.join(fields)}\nSIZE {' '.join(map(str, sizes))}\n"
            f"TYPE {' '.join(types)}\nCOUNT {' '.join(map(str, counts))}\n"
            f"WIDTH {width}\nHEIGHT {height}\nVIEWPOINT 0 0 0 1 0 0 0\n"
            f"POINTS {width * height}\nDATA {data}\n")


def pcd_ascii(points, width=None, height=1, fmt="{:.6g}"):
    width = width or len(points)
    body = "".join(" ".join(fmt.format(c) if isinstance(c, float) else str(c) for c in p) + "\n"
                   for p in points)
    return pcd_header(["x", "y", "z"], [4] * 3, ["F"] * 3, [1] * 3, width, height, "ascii") + body


def lzf_literal(data):
    """An LZF stream of literal runs only (valid for PCL's decompressor)."""
    out = bytearray()
    for i in range(0, len(data), 32):
        chunk = data[i:i + 32]
        out.append(len(chunk) - 1)
        out += chunk
    return bytes(out)


def cloud_file_seeds():
    t = "fuzz_cloud_file"
    pts = sphere(20, 1)
    write(t, "pcd_ascii_xyz.pcd", pcd_ascii(pts))
    # Binary with a packed rgb field.
    pts = sphere(30, 2)
    body = b"".join(struct.pack("<fffI", *p, 0xff000000 | (i * 2654435761 & 0xffffff))
                    for i, p in enumerate(pts))
    write(t, "pcd_binary_xyzrgb.pcd",
          pcd_header(["x", "y", "z", "rgb"], [4] * 4, ["F", "F", "F", "U"], [1] * 4, 30, 1,
                     "binary").encode() + body)
    # binary_compressed: the fields one after the other, LZF-compressed.
    pts = sphere(20, 3)
    raw = b"".join(struct.pack("<20f", *[p[d] for p in pts]) for d in range(3))
    packed = lzf_literal(raw)
    write(t, "pcd_binary_compressed.pcd",
          pcd_header(["x", "y", "z"], [4] * 3, ["F"] * 3, [1] * 3, 20, 1,
                     "binary_compressed").encode() + struct.pack("<II", len(packed), len(raw)) + packed)
    # Organised 4 x 3 with NaN holes, and double coordinates with an intensity.
    pts = sphere(12, 4)
    pts[3] = pts[7] = ["nan", "nan", "nan"]
    write(t, "pcd_organised_nan.pcd", pcd_ascii(pts, width=4, height=3))
    pts = sphere(16, 5)
    write(t, "pcd_double_intensity.pcd",
          pcd_header(["x", "y", "z", "intensity"], [8, 8, 8, 4], ["F"] * 4, [1] * 4, 16, 1, "ascii")
          + "".join(f"{p[0]!r} {p[1]!r} {p[2]!r} {i * 0.5}\n" for i, p in enumerate(pts)))
    # Edge cases: infinities, huge and geo-referenced values, one point, identical points.
    pts = sphere(20, 6)
    pts[0] = ["inf", 0.0, 0.0]
    pts[1] = [0.0, "-inf", 1.0]
    pts[2] = [1e15, 1e15, 1e15]
    write(t, "pcd_edge_inf_huge.pcd", pcd_ascii(pts))
    pts[2] = [1e30, 1e30, 1e30]  # beyond the 1e18 span: an error
    write(t, "pcd_edge_span_1e30.pcd", pcd_ascii(pts))
    write(t, "pcd_geo_1e7.pcd", pcd_ascii([[4.5e6 + 10 * p[0], 9.9e6 + 10 * p[1], 100 + p[2]]
                                           for p in sphere(25, 7)], fmt="{:.9g}"))
    write(t, "pcd_one_point.pcd", pcd_ascii([[1.5, -2.0, 3.25]]))
    write(t, "pcd_identical.pcd", pcd_ascii([[1.0, 2.0, 3.0]] * 12))
    # PLY: ASCII with colours and a face element, binary little and big endian, doubles.
    pts = sphere(20, 8)
    write(t, "ply_ascii_colour_faces.ply",
          "ply\nformat ascii 1.0\ncomment seed\nelement vertex 20\nproperty float x\n"
          "property float y\nproperty float z\nproperty uchar red\nproperty uchar green\n"
          "property uchar blue\nelement face 2\nproperty list uchar int vertex_indices\n"
          "end_header\n"
          + "".join(f"{p[0]:.6g} {p[1]:.6g} {p[2]:.6g} {i * 9 % 256} {i * 5 % 256} {i * 3 % 256}\n"
                    for i, p in enumerate(pts))
          + "3 0 1 2\n3 2 3 4\n")
    pts = sphere(25, 9)
    header = ("ply\nformat {} 1.0\nelement vertex 25\nproperty float x\nproperty float y\n"
              "property float z\nproperty float intensity\nend_header\n")
    write(t, "ply_binary_le.ply", header.format("binary_little_endian").encode()
          + b"".join(struct.pack("<4f", *p, i * 0.25) for i, p in enumerate(pts)))
    write(t, "ply_binary_be.ply", header.format("binary_big_endian").encode()
          + b"".join(struct.pack(">4f", *p, i * 0.25) for i, p in enumerate(pts)))
    pts = sphere(15, 10)
    write(t, "ply_ascii_double.ply",
          "ply\nformat ascii 1.0\nelement vertex 15\nproperty double x\nproperty double y\n"
          "property double z\nend_header\n" + "".join(f"{p[0]!r} {p[1]!r} {p[2]!r}\n" for p in pts))


def filters_input(params, indices, points):
    """params: 7 bytes; indices: list of bytes; points: (kind, payload bytes) pairs."""
    data = bytearray(params)
    data.append(len(indices))
    data += bytes(indices)
    for kind, payload in points:
        data.append(kind)
        data += payload
    return bytes(data)


def grid_points(pts, scale=256.0):
    out = []
    for p in pts:
        out.append((6, struct.pack("<3h", *[max(-32768, min(32767, int(round(c * scale)))) for c in p])))
    return out


def filters_seeds():
    t = "fuzz_filters"
    # Parameters: flags, k, sigma, gamma (255 = automatic), radius, rule, iterations.
    default = [0, 10, 0, 255, 0, 3, 0x1A]  # max_iterations 10, graph iterations 1
    write(t, "sphere_defaults", filters_input(default, [], grid_points(sphere(60, 11))))
    # Organised (flag 128), kept organised (64), with NaN holes (kind 7).
    pts = grid_points(sphere(48, 12))
    for i in range(0, 48, 5):
        pts[i] = (7, b"")
    write(t, "organised_holes", filters_input([128 | 64, 8, 0, 255, 0, 0 | (28 << 3), 0x1A], [], pts))
    # Index lists: repeated, out of range (200+), negative (255).
    write(t, "indices_bad", filters_input(default, [0, 1, 2, 2, 5, 250, 255, 7],
                                          grid_points(sphere(40, 13))))
    write(t, "indices_repeated", filters_input(default, [3, 4, 5, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12],
                                               grid_points(sphere(40, 14))))
    # Table values: NaN (18), Inf (19), -Inf (20), huge (16, 17), float max (23).
    pts = grid_points(sphere(40, 15)) + [(3, bytes([18, 0, 0])), (3, bytes([19, 20, 0])),
                                          (3, bytes([16, 16, 16])), (3, bytes([23, 0, 0]))]
    write(t, "extreme_values", filters_input(default, [], pts))
    # Huge gamma with CHOLMOD and a plane surface; huge sigma and radius; fraction 1.
    write(t, "huge_gamma_cholmod", filters_input([1 | 4, 10, 17, 17, 17, 2 | (10 << 3), 0x1F], [],
                                                 grid_points(sphere(50, 16))))
    # Tiny gamma, anisotropic TV, no refinements, two threads, strict tolerance.
    write(t, "tiny_gamma_anisotropic", filters_input([2 | 8 | 16, 6, 3, 1, 0, 1 | (4 << 3), 0xDF], [],
                                                     grid_points(sphere(50, 17))))
    # The own quadric (sigma byte bit 6) over two rings (bit 5: no adaptive support).
    write(t, "own_quadric_two_rings", filters_input([0, 10, 64 | 32, 255, 0, 3, 0x1A], [],
                                                    grid_points(sphere(60, 21))))
    # A blended quadric at every point (sigma byte bit 7: patch cover 0), automatic gamma.
    write(t, "every_point_quadric", filters_input([0, 10, 128, 255, 0, 3, 0x1A], [],
                                                  grid_points(sphere(60, 22))))
    # Geo-referenced (kind 5), micrometres (kind 4), duplicates (kind 2), k = INT_MAX.
    rng = random.Random(18)
    geo = [(5, bytes(rng.randrange(256) for _ in range(3))) for _ in range(40)]
    write(t, "geo_1e7", filters_input(default, [], geo))
    micro = [(4, bytes(rng.randrange(256) for _ in range(3))) for _ in range(40)]
    write(t, "micrometres", filters_input(default, [], micro))
    dup = []
    for p in grid_points(sphere(20, 19)):
        dup += [p, (2, b""), (2, b"")]
    write(t, "duplicates_k_max", filters_input([0, 255, 0, 255, 0, 3, 0x1A], [], dup))
    # Collinear and coplanar (kind 0: a grid of 1/16).
    line = [(0, struct.pack("3b", i, 2 * i, -i)) for i in range(-30, 30)]
    write(t, "collinear", filters_input(default, [], line))
    plane = [(0, struct.pack("3b", i, j, 0)) for i in range(-4, 4) for j in range(-4, 4)]
    write(t, "coplanar", filters_input(default, [], plane))
    # Invalid parameters: k = 0, negative sigma, graph iterations 0, maximum iterations 0.
    write(t, "invalid_parameters", filters_input([0, 0, 21, 21, 21, 2 | (21 << 3), 0x00], [],
                                                 grid_points(sphere(20, 20))))
    # One point, two points, nothing.
    write(t, "one_point", filters_input(default, [], grid_points(sphere(1, 21))))
    write(t, "two_points", filters_input(default, [], grid_points(sphere(2, 22))))
    write(t, "empty", bytes(default) + b"\x00")


if __name__ == "__main__":
    cloud_file_seeds()
    filters_seeds()
