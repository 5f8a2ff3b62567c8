#!/usr/bin/env python3
"""Convert a v/f-only OBJ to binary little-endian PLY (same vertices, same triangles).

Used once to store the 69k-triangle Stanford bunny in configs/models at half the
size of its OBJ text. Usage: obj_to_binary_ply.py IN.obj OUT.ply
"""
import struct
import sys


def main():
    if len(sys.argv) != 3 or sys.argv[1] in ("-h", "--help"):
        print(__doc__)
        return 0 if len(sys.argv) == 2 else 2
    vertices, faces = [], []
    with open(sys.argv[1]) as obj:
        for line in obj:
            parts = line.split()
            if not parts:
                continue
            if parts[0] == "v":
                vertices.append(tuple(float(x) for x in parts[1:4]))
            elif parts[0] == "f":
                idx = [int(p.split("/")[0]) for p in parts[1:]]
                idx = [i - 1 if i > 0 else len(vertices) + i for i in idx]
                for k in range(1, len(idx) - 1):
                    faces.append((idx[0], idx[k], idx[k + 1]))
    header = (
        "ply\nformat binary_little_endian 1.0\n"
        f"comment converted from {sys.argv[1].split('/')[-1]} by tools/models/obj_to_binary_ply.py\n"
        f"element vertex {len(vertices)}\nproperty float x\nproperty float y\nproperty float z\n"
        f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n"
    )
    with open(sys.argv[2], "wb") as out:
        out.write(header.encode("ascii"))
        for v in vertices:
            out.write(struct.pack("<3f", *v))
        for f in faces:
            out.write(struct.pack("<B3i", 3, *f))
    print(f"{len(vertices)} vertices, {len(faces)} triangles -> {sys.argv[2]}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
