#!/usr/bin/env python3
"""Writes textured-bottle.glb: a glass wine bottle (a lathe, closed, 0.5 mm of air between glass and
wine), the wine (a closed cylinder), and a paper label (an open band around the body with texture
coordinates) whose baseColorTexture is a PNG this script draws and embeds. textured-bottle.json
renders it: the scene gives the glass and the wine their media by material name.

Run: /usr/bin/python3 scenes/examples/make_textured_bottle.py [OUT.glb]  (numpy; no other package)
The output is deterministic: the committed .glb is what the script writes.
"""
import json
import struct
import sys
import zlib
from pathlib import Path

import numpy as np

SEGMENTS = 96


def lathe(profile, segments=SEGMENTS):
    """A closed surface of revolution about +y from (r, y) points that start and end on the axis."""
    positions, rings = [], []
    for r, y in profile:
        if r == 0.0:
            rings.append([len(positions)])
            positions.append((0.0, y, 0.0))
        else:
            ring = []
            for j in range(segments):
                a = 2.0 * np.pi * j / segments
                ring.append(len(positions))
                positions.append((r * np.sin(a), y, r * np.cos(a)))
            rings.append(ring)
    triangles = []
    for a, b in zip(rings, rings[1:]):
        for j in range(segments):
            k = (j + 1) % segments
            if len(a) == 1:
                triangles.append((a[0], b[k], b[j]))
            elif len(b) == 1:
                triangles.append((a[j], a[k], b[0]))
            else:
                triangles += [(a[j], a[k], b[k]), (a[j], b[k], b[j])]
    p = np.array(positions, dtype=np.float64)
    t = np.array(triangles, dtype=np.uint32)
    volume = np.einsum("ij,ij->i", p[t[:, 0]], np.cross(p[t[:, 1]], p[t[:, 2]])).sum() / 6.0
    if volume < 0.0:  # wound inward: turn every face
        t = t[:, [0, 2, 1]]
    return p.astype(np.float32), t


def label_band(radius, y0, y1, arc_rad, segments=SEGMENTS, rows=4):
    """An open band of a cylinder facing +z, u along the arc, v (glTF: down the image) along y."""
    positions, uvs = [], []
    for i in range(rows + 1):
        f = i / rows
        y = y0 + (y1 - y0) * f
        for j in range(segments + 1):
            u = j / segments
            a = (u - 0.5) * arc_rad
            positions.append((radius * np.sin(a), y, radius * np.cos(a)))
            uvs.append((u, 1.0 - f))
    triangles = []
    w = segments + 1
    for i in range(rows):
        for j in range(segments):
            q = i * w + j
            triangles += [(q, q + 1, q + w + 1), (q, q + w + 1, q + w)]  # outward (+r) facing
    return (np.array(positions, dtype=np.float32), np.array(triangles, dtype=np.uint32),
            np.array(uvs, dtype=np.float32))


def label_image(width=512, height=256):
    """The label, drawn here: cream paper, a claret band, a grape cluster, a double border. sRGB."""
    y, x = np.mgrid[0:height, 0:width].astype(np.float64)
    img = np.empty((height, width, 3))
    img[:] = (236, 226, 200)  # cream
    band = (y > 0.62 * height) & (y < 0.80 * height)
    img[band] = (112, 20, 38)  # claret
    for inset, thickness in ((10, 4), (20, 2)):  # border lines
        edge = ((np.abs(x - inset) < thickness) | (np.abs(x - (width - 1 - inset)) < thickness) |
                (np.abs(y - inset) < thickness) | (np.abs(y - (height - 1 - inset)) < thickness))
        inside = (x >= inset - thickness) & (x <= width - 1 - inset + thickness) & \
                 (y >= inset - thickness) & (y <= height - 1 - inset + thickness)
        img[edge & inside] = (60, 40, 30)
    cx, cy, r = width / 2, 0.34 * height, 0.045 * height  # grapes: rows of 4, 3, 2, 1
    for row, count in enumerate((4, 3, 2, 1)):
        for k in range(count):
            gx = cx + (k - (count - 1) / 2) * 2.1 * r
            gy = cy - 0.12 * height + row * 1.8 * r
            img[(x - gx) ** 2 + (y - gy) ** 2 < r * r] = (74, 30, 92)
    leaf = ((x - cx - 1.6 * r) ** 2 / 4 + (y - cy + 0.2 * height) ** 2) < (0.8 * r) ** 2
    img[leaf] = (60, 110, 40)
    return img.astype(np.uint8)


def png_bytes(img):
    """An 8-bit RGB PNG (no filter), written with zlib."""
    h, w, _ = img.shape
    raw = b"".join(b"\x00" + img[row].tobytes() for row in range(h))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


class Glb:
    def __init__(self):
        self.doc = {"asset": {"version": "2.0", "generator": "bouguer scenes/examples/make_textured_bottle.py"},
                    "scene": 0, "scenes": [{"nodes": []}], "nodes": [], "meshes": [], "materials": [],
                    "accessors": [], "bufferViews": [], "buffers": [{"byteLength": 0}]}
        self.bin = bytearray()

    def view(self, data):
        while len(self.bin) % 4:
            self.bin.append(0)
        self.doc["bufferViews"].append({"buffer": 0, "byteOffset": len(self.bin), "byteLength": len(data)})
        self.bin += data
        return len(self.doc["bufferViews"]) - 1

    def accessor(self, array, kind, minmax=False):
        component = 5125 if array.dtype == np.uint32 else 5126
        acc = {"bufferView": self.view(array.tobytes()), "componentType": component,
               "count": int(array.shape[0]) * (3 if kind == "SCALAR" else 1), "type": kind}
        if minmax:
            acc["min"] = [float(v) for v in array.min(axis=0)]
            acc["max"] = [float(v) for v in array.max(axis=0)]
        self.doc["accessors"].append(acc)
        return len(self.doc["accessors"]) - 1

    def add(self, name, positions, triangles, material, uvs=None):
        attributes = {"POSITION": self.accessor(positions, "VEC3", minmax=True)}
        if uvs is not None:
            attributes["TEXCOORD_0"] = self.accessor(uvs, "VEC2")
        self.doc["meshes"].append({"name": name, "primitives": [
            {"attributes": attributes, "indices": self.accessor(triangles, "SCALAR"), "material": material}]})
        self.doc["nodes"].append({"name": name, "mesh": len(self.doc["meshes"]) - 1})
        self.doc["scenes"][0]["nodes"].append(len(self.doc["nodes"]) - 1)

    def material(self, m):
        self.doc["materials"].append(m)
        return len(self.doc["materials"]) - 1

    def write(self, path):
        while len(self.bin) % 4:
            self.bin.append(0)
        self.doc["buffers"][0]["byteLength"] = len(self.bin)
        text = json.dumps(self.doc, separators=(",", ":")).encode()
        text += b" " * (-len(text) % 4)
        body = struct.pack("<II", len(text), 0x4E4F534A) + text + struct.pack("<II", len(self.bin), 0x004E4942) + self.bin
        Path(path).write_bytes(struct.pack("<III", 0x46546C67, 2, 12 + len(body)) + body)


def main():
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).with_name("textured-bottle.glb")
    g = Glb()
    glass = g.material({"name": "Glass", "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "roughnessFactor": 0},
                        "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1},
                                       "KHR_materials_volume": {"thicknessFactor": 0.003}}})
    wine = g.material({"name": "Wine", "pbrMetallicRoughness": {"roughnessFactor": 0},
                       "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1},
                                      "KHR_materials_volume": {"thicknessFactor": 0.06}}})
    g.doc["images"] = [{"bufferView": g.view(png_bytes(label_image())), "mimeType": "image/png", "name": "label"}]
    g.doc["textures"] = [{"source": 0}]
    paper = g.material({"name": "Label", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0},
                                                                  "metallicFactor": 0, "roughnessFactor": 1}})
    g.doc["extensionsUsed"] = ["KHR_materials_transmission", "KHR_materials_volume"]
    # Metres: a 75 mm bottle, 300 mm tall, 3 mm walls; wine to 160 mm, 0.5 mm short of the glass.
    outer = [(0.0, 0.0), (0.0365, 0.0), (0.0375, 0.002), (0.0375, 0.195), (0.033, 0.222), (0.022, 0.24),
             (0.0145, 0.255), (0.0135, 0.3), (0.0105, 0.3)]
    inner = [(0.0105, 0.255), (0.018, 0.238), (0.029, 0.222), (0.0345, 0.196), (0.0345, 0.006), (0.0, 0.006)]
    g.add("bottle", *lathe(outer + inner), glass)
    g.add("wine", *lathe([(0.0, 0.0065), (0.034, 0.0065), (0.034, 0.16), (0.0, 0.16)]), wine)
    band, band_triangles, band_uvs = label_band(0.0382, 0.05, 0.15, 1.6 * np.pi)
    g.add("label", band, band_triangles, paper, uvs=band_uvs)
    g.write(out)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
