#!/usr/bin/env python3
"""Converts an OFF mesh (e.g. CGAL's data/meshes/*.off from Debian's libcgal-demo) to OBJ,
optionally splitting every triangle into four at its edge midpoints N times (4^N triangles each),
to make big test meshes for `frameless bench build`.

Usage: tools/off_to_obj.py IN.off OUT.obj [--subdivide N]
"""
import argparse
import sys


def read_off(path):
    tokens = []
    with open(path) as f:
        for line in f:
            line = line.split('#', 1)[0].split()
            tokens.extend(line)
    if not tokens or tokens[0] != 'OFF':
        sys.exit(f'{path}: not an OFF file')
    nv, nf = int(tokens[1]), int(tokens[2])
    pos = 4
    verts = []
    for _ in range(nv):
        verts.append(tuple(float(t) for t in tokens[pos:pos + 3]))
        pos += 3
    tris = []
    for _ in range(nf):
        k = int(tokens[pos])
        idx = [int(t) for t in tokens[pos + 1:pos + 1 + k]]
        pos += 1 + k
        for i in range(1, k - 1):  # fan-triangulate polygons
            tris.append((idx[0], idx[i], idx[i + 1]))
    return verts, tris


def subdivide(verts, tris):
    mid = {}

    def m(a, b):
        key = (a, b) if a < b else (b, a)
        if key not in mid:
            va, vb = verts[a], verts[b]
            verts.append(tuple((x + y) * 0.5 for x, y in zip(va, vb)))
            mid[key] = len(verts) - 1
        return mid[key]

    out = []
    for a, b, c in tris:
        ab, bc, ca = m(a, b), m(b, c), m(c, a)
        out += [(a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca)]
    return verts, out


def main():
    p = argparse.ArgumentParser()
    p.add_argument('input')
    p.add_argument('output')
    p.add_argument('--subdivide', type=int, default=0)
    a = p.parse_args()
    verts, tris = read_off(a.input)
    for _ in range(a.subdivide):
        verts, tris = subdivide(verts, tris)
    with open(a.output, 'w') as f:
        f.write(''.join(f'v {x:.6g} {y:.6g} {z:.6g}\n' for x, y, z in verts))
        f.write(''.join(f'f {a + 1} {b + 1} {c + 1}\n' for a, b, c in tris))
    print(f'{a.output}: {len(verts)} vertices, {len(tris)} triangles')


if __name__ == '__main__':
    main()
