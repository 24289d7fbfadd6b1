#!/usr/bin/env python3
"""Independent reference for tests/import_models.rs: skinned positions of a few vertices of the
shared models at one animation time, computed from the GLB bytes by hand (numpy, no glTF library),
following the glTF 2.0 spec directly:

- GLB chunks, accessors (float / u8 / u16 components, byteStride) read with struct + numpy;
- animation sampling: STEP holds the previous key, LINEAR lerps translations/scales and slerps
  rotations along the shortest arc; times outside the keys clamp to the first/last key;
- node matrices T * R * S composed parent-first from the scene roots (model space = scene root);
- linear blend skinning: sum_k w_k * model_from_joint_k * inverse_bind_k * p, with the weights
  divided by their sum (the importer renormalizes the same way).

The vertex is named by a *corner* (a position in the primitive's index list, or the vertex number
of a non-indexed primitive), because the importer welds non-indexed meshes such as Fox.

Run once: `python3 tests/reference/skin_reference.py ../shared/models` and paste its output into the
test. Not run by `cargo test`.
"""
import json
import struct
import sys

import numpy as np

COMPONENT = {5120: ("b", 1), 5121: ("B", 1), 5122: ("h", 2), 5123: ("H", 2), 5125: ("I", 4), 5126: ("f", 4)}
NCOMP = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT4": 16}


def load(path):
    data = open(path, "rb").read()
    magic, version, length = struct.unpack_from("<4sII", data, 0)
    assert magic == b"glTF" and version == 2
    jlen, jtype = struct.unpack_from("<II", data, 12)
    doc = json.loads(data[20 : 20 + jlen])
    at = 20 + jlen
    blen, btype = struct.unpack_from("<II", data, at)
    return doc, data[at + 8 : at + 8 + blen]


def accessor(doc, bin_, i):
    a = doc["accessors"][i]
    v = doc["bufferViews"][a["bufferView"]]
    fmt, size = COMPONENT[a["componentType"]]
    n = NCOMP[a["type"]]
    stride = v.get("byteStride", size * n)
    base = v.get("byteOffset", 0) + a.get("byteOffset", 0)
    out = np.array(
        [struct.unpack_from("<" + fmt * n, bin_, base + k * stride) for k in range(a["count"])], dtype=np.float64
    )
    if a.get("normalized"):
        out /= {"B": 255.0, "H": 65535.0}[fmt]
    return out


def quat_matrix(q):
    x, y, z, w = q / np.linalg.norm(q)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def slerp(a, b, s):
    a = a / np.linalg.norm(a)
    b = b / np.linalg.norm(b)
    d = np.dot(a, b)
    if d < 0:
        b, d = -b, -d
    if d > 0.9995:
        r = a + s * (b - a)
        return r / np.linalg.norm(r)
    theta = np.arccos(d)
    return (np.sin((1 - s) * theta) * a + np.sin(s * theta) * b) / np.sin(theta)


def sample(times, values, interp, path, t):
    if t <= times[0]:
        return values[0]
    if t >= times[-1]:
        return values[-1]
    k = np.searchsorted(times, t, side="right") - 1
    if interp == "STEP":
        return values[k]
    s = (t - times[k]) / (times[k + 1] - times[k])
    if path == "rotation":
        return slerp(values[k], values[k + 1], s)
    return values[k] + s * (values[k + 1] - values[k])


def local_matrix(trs):
    m = np.eye(4)
    m[:3, :3] = quat_matrix(trs["rotation"]) * trs["scale"][None, :]
    m[:3, 3] = trs["translation"]
    return m


def skinned(path, clip, t, corners):
    doc, bin_ = load(path)
    nodes = doc["nodes"]
    trs = []
    for n in nodes:
        assert "matrix" not in n
        trs.append(
            {
                "translation": np.array(n.get("translation", [0, 0, 0]), dtype=np.float64),
                "rotation": np.array(n.get("rotation", [0, 0, 0, 1]), dtype=np.float64),
                "scale": np.array(n.get("scale", [1, 1, 1]), dtype=np.float64),
            }
        )
    anim = next(a for a in doc["animations"] if a.get("name") == clip)
    for ch in anim["channels"]:
        smp = anim["samplers"][ch["sampler"]]
        times = accessor(doc, bin_, smp["input"])[:, 0]
        values = accessor(doc, bin_, smp["output"])
        prop = ch["target"]["path"]
        trs[ch["target"]["node"]][prop] = sample(times, values, smp.get("interpolation", "LINEAR"), prop, t)
    world = [None] * len(nodes)

    def visit(i, parent):
        world[i] = parent @ local_matrix(trs[i])
        for c in nodes[i].get("children", []):
            visit(c, world[i])

    for r in doc["scenes"][doc.get("scene", 0)]["nodes"]:
        visit(r, np.eye(4))
    mesh_node = next(n for n in nodes if "mesh" in n and "skin" in n)
    skin = doc["skins"][mesh_node["skin"]]
    ibm = accessor(doc, bin_, skin["inverseBindMatrices"]).reshape(-1, 4, 4).transpose(0, 2, 1)
    joint_mats = [world[j] @ ibm[k] for k, j in enumerate(skin["joints"])]
    prim = doc["meshes"][mesh_node["mesh"]]["primitives"][0]
    pos = accessor(doc, bin_, prim["attributes"]["POSITION"])
    joints = accessor(doc, bin_, prim["attributes"]["JOINTS_0"]).astype(int)
    weights = accessor(doc, bin_, prim["attributes"]["WEIGHTS_0"])
    indices = accessor(doc, bin_, prim["indices"])[:, 0].astype(int) if "indices" in prim else None
    out = []
    for c in corners:
        v = indices[c] if indices is not None else c
        w = weights[v] / weights[v].sum()
        m = sum(w[k] * joint_mats[joints[v][k]] for k in range(4))
        p = m @ np.append(pos[v], 1.0)
        out.append((c, p[:3]))
    return out


def distinct_corners(path):
    """Vertices of a non-indexed primitive that differ in some attribute: what welding must leave."""
    doc, bin_ = load(path)
    prim = doc["meshes"][0]["primitives"][0]
    cols = [accessor(doc, bin_, a).astype(np.float32) for a in prim["attributes"].values()]
    return len({tuple(np.concatenate([c[i] for c in cols]).tolist()) for i in range(len(cols[0]))})


if __name__ == "__main__":
    root = sys.argv[1] if len(sys.argv) > 1 else "../shared/models"
    cases = [
        # Corners: the first one, and two that move far from the bind pose at that time.
        ("CesiumMan.glb", "Anim_0", 0.9, [0, 7028, 8778]),
        ("Fox.glb", "Walk", 0.3, [0, 1477, 1610]),
        ("RiggedSimple.glb", "Anim_0_Armature", 1.3, [0, 1267, 2436]),
    ]
    for name, clip, t, corners in cases:
        for c, p in skinned(f"{root}/{name}", clip, t, corners):
            print(f"{name} {clip} t={t} corner {c}: [{p[0]:.6f}, {p[1]:.6f}, {p[2]:.6f}]")
    print("Fox.glb distinct corners:", distinct_corners(f"{root}/Fox.glb"))
