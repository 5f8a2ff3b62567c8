#!/usr/bin/env python3
"""Decimates a triangle mesh by vertex clustering (Rossignac & Borrel 1993): vertices are
snapped to a uniform grid, each occupied cell becomes one vertex (the mean of its members),
and triangles that collapse are dropped. Fast and crude, fine for a render mesh seen small
on screen; the cell size is searched so the result has about --triangles triangles.
Reads and writes Wavefront OBJ (v and f lines). Standard library only.

  tools/models/decimate_vertex_clustering.py IN.obj OUT.obj --triangles 1200
"""
import argparse


def read_obj(path):
    vertices, faces = [], []
    for line in open(path):
        parts = line.split()
        if not parts:
            continue
        if parts[0] == "v":
            vertices.append(tuple(float(x) for x in parts[1:4]))
        elif parts[0] == "f":
            idx = [int(p.split("/")[0]) - 1 for p in parts[1:]]
            for k in range(1, len(idx) - 1):
                faces.append((idx[0], idx[k], idx[k + 1]))
    return vertices, faces


def cluster(vertices, faces, cell):
    cells, new_vertices, counts, remap = {}, [], [], []
    lo = [min(v[i] for v in vertices) for i in range(3)]
    for v in vertices:
        key = tuple(int((v[i] - lo[i]) // cell) for i in range(3))
        if key not in cells:
            cells[key] = len(new_vertices)
            new_vertices.append([0.0, 0.0, 0.0])
            counts.append(0)
        j = cells[key]
        for i in range(3):
            new_vertices[j][i] += v[i]
        counts[j] += 1
        remap.append(j)
    new_vertices = [[c / n for c in v] for v, n in zip(new_vertices, counts)]
    seen, new_faces = set(), []
    for a, b, c in faces:
        a, b, c = remap[a], remap[b], remap[c]
        if a == b or b == c or a == c:
            continue
        key = tuple(sorted((a, b, c)))
        if key in seen:
            continue
        seen.add(key)
        new_faces.append((a, b, c))
    return new_vertices, new_faces


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("input")
    parser.add_argument("output")
    parser.add_argument("--triangles", type=int, default=1200, help="target triangle count")
    args = parser.parse_args()
    vertices, faces = read_obj(args.input)
    extent = max(max(v[i] for v in vertices) - min(v[i] for v in vertices) for i in range(3))
    lo_cell, hi_cell = extent / 2000, extent / 5
    for _ in range(40):  # bisect the cell size on the triangle count
        cell = (lo_cell * hi_cell) ** 0.5
        nv, nf = cluster(vertices, faces, cell)
        if len(nf) > args.triangles:
            lo_cell = cell
        else:
            hi_cell = cell
    nv, nf = cluster(vertices, faces, hi_cell)
    used = sorted({i for f in nf for i in f})
    index = {old: new for new, old in enumerate(used)}
    with open(args.output, "w") as out:
        out.write(f"# {args.input.split('/')[-1]} decimated by vertex clustering (cell {hi_cell:.6g}) to {len(nf)} triangles\n")
        out.write(f"# by tools/models/decimate_vertex_clustering.py\n")
        for i in used:
            out.write("v %.6f %.6f %.6f\n" % tuple(nv[i]))
        for a, b, c in nf:
            out.write(f"f {index[a] + 1} {index[b] + 1} {index[c] + 1}\n")
    print(f"{args.output}: {len(used)} vertices, {len(nf)} triangles (from {len(faces)})")


if __name__ == "__main__":
    main()
