"""Reads the PLY files Firn writes (engine/io/Ply.cpp, engine/io/SurfaceMesh.cpp): binary little-endian, one
`vertex` element of float properties (the point caches' x y z vx vy vz mass plastic_j; the surface meshes' x y z
nx ny nz, and vx vy vz when they carry velocities) and, in a surface mesh, a `face` element of triangles as a list
of uchar count and uint vertex_indices. Blender's own PLY importer drops every property but positions, normals
and colours, so the add-on reads these itself."""

import numpy as np


class FirnPlyError(ValueError):
    pass


def read_ply(path):
    """Returns (vertices, triangles): a dict of float32 arrays by property name, and an (n, 3) uint32 array of
    vertex indices (empty when the file has no faces)."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.find(b"end_header\n")
    if not data.startswith(b"ply\n") or end < 0:
        raise FirnPlyError(f"{path}: not a PLY file")
    header = data[:end].decode("ascii").splitlines()
    body = memoryview(data)[end + len(b"end_header\n"):]
    if "format binary_little_endian 1.0" not in header:
        raise FirnPlyError(f"{path}: not binary little-endian PLY")
    elements = []  # (name, count, properties)
    for line in header:
        words = line.split()
        if not words:
            continue
        if words[0] == "element":
            elements.append((words[1], int(words[2]), []))
        elif words[0] == "property":
            if not elements:
                raise FirnPlyError(f"{path}: a property before any element")
            elements[-1][2].append(words[1:])
    vertices, triangles = {}, np.zeros((0, 3), dtype=np.uint32)
    offset = 0
    for name, count, properties in elements:
        if name == "vertex":
            if any(p[0] != "float" for p in properties):
                raise FirnPlyError(f"{path}: vertex properties other than float")
            names = [p[1] for p in properties]
            record = np.dtype([(n, "<f4") for n in names])
            table = np.frombuffer(body, dtype=record, count=count, offset=offset)
            offset += count * record.itemsize
            vertices = {n: np.ascontiguousarray(table[n]) for n in names}
        elif name == "face":
            if properties != [["list", "uchar", "uint", "vertex_indices"]]:
                raise FirnPlyError(f"{path}: faces other than Firn's triangles")
            record = np.dtype([("count", "u1"), ("indices", "<u4", (3,))])
            table = np.frombuffer(body, dtype=record, count=count, offset=offset)
            offset += count * record.itemsize
            if count and np.any(table["count"] != 3):
                raise FirnPlyError(f"{path}: a face that is not a triangle")
            triangles = np.ascontiguousarray(table["indices"])
        else:
            raise FirnPlyError(f"{path}: an element {name!r} Firn does not write")
    if offset != len(body):
        raise FirnPlyError(f"{path}: {len(body) - offset} bytes more or fewer than the header describes")
    return vertices, triangles


def vectors(vertices, names):
    """The (n, 3) float32 array of three named properties."""
    return np.stack([vertices[n] for n in names], axis=1)
