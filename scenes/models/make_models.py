#!/usr/bin/env python3
# Writes scenes/models/cornell-box-mm.obj and cornell-box-original.obj/.mtl from scenes/cornell-box/*.obj
import re
src = 'scenes/cornell-box/'
parts = [('floor_ceiling_back','walls_white.obj','white'),('left_red','wall_red.obj','red'),
         ('right_green','wall_green.obj','green'),('blocks','blocks.obj','white'),('light','light.obj','light')]
objs = []
for name, f, mat in parts:
    vs, fs = [], []
    for line in open(src+f):
        w = line.split()
        if not w or w[0].startswith('#'): continue
        if w[0]=='v': vs.append(tuple(float(x) for x in w[1:4]))
        if w[0]=='f': fs.append(tuple(int(x) for x in w[1:4]))
    objs.append((name, mat, vs, fs))

def fmt(x):
    s = ('%.4f' % x).rstrip('0').rstrip('.')
    return '0' if s in ('-0','') else s

# 1. millimetres, no materials, open at -Z, no emission (like a CAD export of the Cornell data)
out = ['# Cornell box, the published Cornell geometry in millimetres, as a CAD tool exports it:',
       '# one file, no material library, no light (the light is plain geometry), open side at -Z.',
       '# Written for quasar from scenes/cornell-box/*.obj (see SOURCE.md there). Licence: MIT OR Apache-2.0.']
base = 0
for name, mat, vs, fs in objs:
    out.append('o ' + name)
    for v in vs: out.append('v ' + ' '.join(fmt(c*1000) for c in v) + '  # mm')
    for f in fs: out.append('f ' + ' '.join(str(i+base) for i in f))
    base += len(vs)
open('scenes/models/cornell-box-mm.obj','w').write('\n'.join(out)+'\n')

# 2. a 2-unit box centred on x = z = 0, open side at +Z (rotated 180 degrees about +Y), with an
# MTL whose lines carry trailing comments and a Ke light, in the style of common public copies
s = 2.0 / 0.5488
out = ['# Cornell box, 2 units tall, centred on the y axis, open side towards +Z, with an MTL light.',
       '# Written for quasar from scenes/cornell-box/*.obj (see SOURCE.md there). Licence: MIT OR Apache-2.0.',
       'mtllib cornell-box-original.mtl']
base = 0
for name, mat, vs, fs in objs:
    out.append('o ' + name + '  # object')
    for (x, y, z) in vs:
        out.append('v %s %s %s' % (fmt(-(x-0.278)*s), fmt(y*s), fmt(-(z-0.2796)*s)))
    out.append('usemtl ' + mat)
    for f in fs: out.append('f ' + ' '.join(str(i+base) for i in f))
    base += len(vs)
open('scenes/models/cornell-box-original.obj','w').write('\n'.join(out)+'\n')
mtl = """# Materials of cornell-box-original.obj (diffuse, RGB), with trailing comments as public copies have.
# Licence: MIT OR Apache-2.0.
newmtl white
Ka 0.73 0.73 0.73 # ambient, ignored
Kd 0.73 0.73 0.73 # White
Ks 0 0 0
illum 1

newmtl red
Ka 0.63 0.065 0.05 # Red
Kd 0.63 0.065 0.05 # Red
Ks 0 0 0
illum 1

newmtl green
Kd 0.14 0.45 0.091 # Green
Ks 0 0 0
illum 1

newmtl light
Kd 0.78 0.78 0.78
Ke 17 12 4 # warm white, radiance
illum 1
"""
open('scenes/models/cornell-box-original.mtl','w').write(mtl)

# 3. a unit box as glTF with an embedded (data URI) buffer, no camera, no light and COLOR_0
# vertex colours, in the style of the Khronos Box / BoxVertexColors samples
import base64, json, struct

def box(c, s):
    """An axis-aligned box centred at `c` with sides `s`: six outward quads (positions, normals,
    indices, and UVs from x and z)."""
    p, n, ix = [], [], []
    for axis in range(3):
        for sign in (1.0, -1.0):
            nn = [0.0, 0.0, 0.0]; nn[axis] = sign
            u = [0.0, 0.0, 0.0]; u[(axis + 1) % 3] = 1.0
            v = [0.0, 0.0, 0.0]; v[(axis + 2) % 3] = 1.0
            if sign < 0: u, v = v, u
            b = len(p)
            for a, bb in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                p.append(tuple(c[k] + 0.5 * s[k] * (nn[k] + a * u[k] + bb * v[k]) for k in range(3)))
                n.append(tuple(nn))
            ix += [b, b + 1, b + 2, b, b + 2, b + 3]
    uv = [(q[0] - c[0] + 0.5, q[2] - c[2] + 0.5) for q in p]
    return p, n, ix, uv

pos, nrm, idx, _ = box((0.0, 0.0, 0.0), (1.0, 1.0, 1.0))
col = [[0.5 + 0.5 * n[0], 0.5 + 0.5 * n[1], 0.5 + 0.5 * n[2]] for n in nrm]
blob = b''.join(struct.pack('<3f', *p) for p in pos)
blob += b''.join(struct.pack('<3f', *p) for p in nrm)
blob += b''.join(struct.pack('<3f', *p) for p in col)
blob += b''.join(struct.pack('<H', i) for i in idx)
nv = len(pos)
doc = {
    "asset": {"version": "2.0", "generator": "quasar scenes/models/make_models.py",
              "copyright": "written for quasar, MIT OR Apache-2.0"},
    "buffers": [{"byteLength": len(blob), "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
    "bufferViews": [{"buffer": 0, "byteOffset": 12 * nv * k, "byteLength": 12 * nv, "target": 34962} for k in range(3)]
                   + [{"buffer": 0, "byteOffset": 36 * nv, "byteLength": 2 * len(idx), "target": 34963}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": nv, "type": "VEC3", "min": [-0.5] * 3, "max": [0.5] * 3},
                  {"bufferView": 1, "componentType": 5126, "count": nv, "type": "VEC3"},
                  {"bufferView": 2, "componentType": 5126, "count": nv, "type": "VEC3"},
                  {"bufferView": 3, "componentType": 5123, "count": len(idx), "type": "SCALAR"}],
    "materials": [{"name": "Red", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.1, 0.1, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.6}}],
    "meshes": [{"name": "Box", "primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "COLOR_0": 2}, "indices": 3, "material": 0}]}],
    # tilted so that three faces show
    "nodes": [{"name": "Box", "mesh": 0, "rotation": [0.2798, 0.3647, 0.1159, 0.8805]}],
    "scenes": [{"nodes": [0]}],
    "scene": 0,
}
open('scenes/models/box-vertex-colors.gltf', 'w').write(json.dumps(doc, indent=1) + '\n')

# 4. a coated-paint and tail-light model in the manner of Khronos' ClearCoatTest,
# ClearCoatCarPaint and ToyCar: spheres of clear-coated paint (smooth and satin coats), a
# clear-coated metal and an uncoated reference, in a grey box open at the front, lit only by an
# emissive panel
# whose emissive texture is mostly black (two lit "lamp" stripes), with
# KHR_materials_clearcoat in extensionsRequired (ClearCoatCarPaint's declaration). No camera.
import math, zlib

def png_rgba(w, h, pixel):
    raw = b''.join(b'\x00' + b''.join(bytes(pixel(x, y)) for x in range(w)) for y in range(h))
    def chunk(t, d):
        return struct.pack('>I', len(d)) + t + d + struct.pack('>I', zlib.crc32(t + d) & 0xffffffff)
    return (b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', w, h, 8, 6, 0, 0, 0))
            + chunk(b'IDAT', zlib.compress(raw, 9)) + chunk(b'IEND', b''))

def sphere(cx, cy, cz, r, nu=24, nv=12):
    p, n, ix, uv = [], [], [], []
    for j in range(nv + 1):
        th = math.pi * j / nv
        for i in range(nu + 1):
            ph = 2 * math.pi * i / nu
            d = (math.sin(th) * math.cos(ph), math.cos(th), math.sin(th) * math.sin(ph))
            p.append((cx + r * d[0], cy + r * d[1], cz + r * d[2])); n.append(d); uv.append((i / nu, j / nv))
    for j in range(nv):
        for i in range(nu):
            a, b = j * (nu + 1) + i, (j + 1) * (nu + 1) + i
            ix += [a, a + 1, b, a + 1, b + 1, b]
    return p, n, ix, uv

def quad(corners, normal, uvs=None):
    return list(corners), [normal] * 4, [0, 1, 2, 0, 2, 3], uvs

meshes = [
    ('ground', quad([(-3, 0, 2), (3, 0, 2), (3, 0, -2), (-3, 0, -2)], (0, 1, 0)), 0),
    ('backdrop', quad([(-3, 0, -2), (3, 0, -2), (3, 4, -2), (-3, 4, -2)], (0, 0, 1)), 0),
    ('left', quad([(-3, 0, 2), (-3, 0, -2), (-3, 4, -2), (-3, 4, 2)], (1, 0, 0)), 0),
    ('right', quad([(3, 0, -2), (3, 0, 2), (3, 4, 2), (3, 4, -2)], (-1, 0, 0)), 0),
    ('paint_smooth', sphere(-1.8, 0.5, 0, 0.5), 1),
    ('paint_satin', sphere(-0.6, 0.5, 0, 0.5), 2),
    ('metal_coated', sphere(0.6, 0.5, 0, 0.5), 3),
    ('paint_bare', sphere(1.8, 0.5, 0, 0.5), 4),
    # the lamp panel overhead, facing down
    ('lamp', quad([(-2.5, 3.9, -1.0), (2.5, 3.9, -1.0), (2.5, 3.9, 1.0), (-2.5, 3.9, 1.0)], (0, -1, 0),
                  [(0, 0), (1, 0), (1, 1), (0, 1)]), 5),
]
def pack_meshes(meshes):
    """Packs [(name, (positions, normals, indices, uvs or None), material)] into one glTF buffer:
    returns (buffer bytes, bufferViews, accessors, meshes)."""
    blob, views, accessors, prims = b'', [], [], []
    def add(data, target, comp, typ, count, mn=None, mx=None):
        nonlocal blob
        while len(blob) % 4: blob += b'\x00'
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data), "target": target})
        blob += data
        a = {"bufferView": len(views) - 1, "componentType": comp, "count": count, "type": typ}
        if mn is not None: a["min"], a["max"] = mn, mx
        accessors.append(a)
        return len(accessors) - 1
    for name, (p, n, ix, uv), mat in meshes:
        attrs = {"POSITION": add(b''.join(struct.pack('<3f', *v) for v in p), 34962, 5126, "VEC3", len(p),
                                 [min(v[k] for v in p) for k in range(3)], [max(v[k] for v in p) for k in range(3)]),
                 "NORMAL": add(b''.join(struct.pack('<3f', *v) for v in n), 34962, 5126, "VEC3", len(n))}
        if uv: attrs["TEXCOORD_0"] = add(b''.join(struct.pack('<2f', *v) for v in uv), 34962, 5126, "VEC2", len(uv))
        prims.append({"name": name, "primitives": [{"attributes": attrs, "material": mat,
                      "indices": add(b''.join(struct.pack('<I', i) for i in ix), 34963, 5125, "SCALAR", len(ix))}]})
    return blob, views, accessors, prims
blob, views, accessors, prims = pack_meshes(meshes)
# 64 x 16 texels: black but for two warm "lamp" stripes
lamp = png_rgba(64, 16, lambda x, y: (255, 200, 150, 255) if 4 <= y < 12 and (6 <= x < 22 or 42 <= x < 58) else (0, 0, 0, 255))
# 32 x 32 tangent-space normals of gentle bumps (orange peel)
def peel_texel(x, y):
    nx, ny = 0.5 * math.sin(2 * math.pi * x / 8), 0.5 * math.sin(2 * math.pi * y / 8)
    nz = math.sqrt(max(0.0, 1 - nx * nx - ny * ny))
    return tuple(int(round(255 * (0.5 + 0.5 * c))) for c in (nx, ny, nz)) + (255,)
peel = png_rgba(32, 32, peel_texel)
red = [0.6, 0.04, 0.03, 1]
doc = {
    "asset": {"version": "2.0", "generator": "scenes/models/make_models.py (quasar)"},
    "extensionsUsed": ["KHR_materials_clearcoat", "KHR_materials_emissive_strength", "KHR_texture_transform"],
    "extensionsRequired": ["KHR_materials_clearcoat", "KHR_texture_transform"],
    "scene": 0, "scenes": [{"nodes": list(range(len(meshes)))}],
    "nodes": [{"mesh": i, "name": m[0]} for i, m in enumerate(meshes)],
    "meshes": prims,
    "materials": [
        {"name": "ground", "pbrMetallicRoughness": {"baseColorFactor": [0.35, 0.35, 0.35, 1], "metallicFactor": 0}},
        # ClearCoatCarPaint's declaration: an orange-peel normal map on the base (scale 0.2,
        # repeated 3 x 3 by KHR_texture_transform, required), the coat without its own map
        {"name": "paint_smooth", "pbrMetallicRoughness": {"baseColorFactor": red, "metallicFactor": 0},
         "normalTexture": {"index": 1, "scale": 0.2, "extensions": {"KHR_texture_transform": {"scale": [3, 3]}}},
         "extensions": {"KHR_materials_clearcoat": {"clearcoatFactor": 1, "clearcoatRoughnessFactor": 0}}},
        {"name": "paint_satin", "pbrMetallicRoughness": {"baseColorFactor": red, "metallicFactor": 0},
         "extensions": {"KHR_materials_clearcoat": {"clearcoatFactor": 1, "clearcoatRoughnessFactor": 0.4}}},
        {"name": "metal_coated", "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.75, 0.4, 1], "metallicFactor": 1, "roughnessFactor": 0.35},
         "extensions": {"KHR_materials_clearcoat": {"clearcoatFactor": 1, "clearcoatRoughnessFactor": 0.05}}},
        {"name": "paint_bare", "pbrMetallicRoughness": {"baseColorFactor": red, "metallicFactor": 0}},
        {"name": "lamp", "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0},
         "emissiveFactor": [1, 1, 1], "emissiveTexture": {"index": 0},
         "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 60}}},
    ],
    "textures": [{"source": 0, "sampler": 0}, {"source": 1, "sampler": 1}],
    "samplers": [{"magFilter": 9728, "minFilter": 9728}, {"magFilter": 9729, "minFilter": 9987}],
    "images": [{"mimeType": "image/png", "uri": "data:image/png;base64," + base64.b64encode(im).decode()}
               for im in (lamp, peel)],
    "accessors": accessors, "bufferViews": views,
    "buffers": [{"byteLength": len(blob), "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
}
open('scenes/models/coated-paint-and-lamp.gltf', 'w').write(json.dumps(doc, indent=1) + '\n')

# 5. a fabric, glass and sign model in the manner of Khronos' SheenChair, TransmissionTest and
# EmissiveStrengthTest: a velvet cushion (KHR_materials_sheen with a striped sheenColorTexture
# and a sheenRoughnessTexture) on a dark frame, clear, frosted and tinted glass spheres
# (KHR_materials_transmission, _ior, _volume with an attenuation colour), three sign tiles on the
# back wall whose emission differs only by KHR_materials_emissive_strength (1, 4, 16), and an
# untextured ceiling panel as the main light. Sheen and transmission in extensionsRequired. No camera.
meshes = [
    ('ground', quad([(-3, 0, 2), (3, 0, 2), (3, 0, -2), (-3, 0, -2)], (0, 1, 0)), 0),
    ('backdrop', quad([(-3, 0, -2), (3, 0, -2), (3, 4, -2), (-3, 4, -2)], (0, 0, 1)), 0),
    ('left', quad([(-3, 0, 2), (-3, 0, -2), (-3, 4, -2), (-3, 4, 2)], (1, 0, 0)), 0),
    ('right', quad([(3, 0, -2), (3, 0, 2), (3, 4, 2), (3, 4, -2)], (-1, 0, 0)), 0),
    ('frame', box((-1.6, 0.2, 0), (1.4, 0.4, 1.2)), 1),
    ('cushion', box((-1.6, 0.55, 0), (1.3, 0.3, 1.1)), 2),
    ('glass_clear', sphere(0.1, 0.45, 0.3, 0.45), 3),
    ('glass_frosted', sphere(1.1, 0.45, 0.3, 0.45), 4),
    ('glass_tinted', sphere(2.1, 0.45, 0.3, 0.45), 5),
    ('sign_1', quad([(-1.5, 2.2, -1.99), (-0.7, 2.2, -1.99), (-0.7, 2.8, -1.99), (-1.5, 2.8, -1.99)], (0, 0, 1)), 6),
    ('sign_4', quad([(-0.4, 2.2, -1.99), (0.4, 2.2, -1.99), (0.4, 2.8, -1.99), (-0.4, 2.8, -1.99)], (0, 0, 1)), 7),
    ('sign_16', quad([(0.7, 2.2, -1.99), (1.5, 2.2, -1.99), (1.5, 2.8, -1.99), (0.7, 2.8, -1.99)], (0, 0, 1)), 8),
    ('ceiling_panel', quad([(-2, 3.9, -1.0), (2, 3.9, -1.0), (2, 3.9, 1.0), (-2, 3.9, 1.0)], (0, -1, 0)), 9),
]
blob, views, accessors, prims = pack_meshes(meshes)
# the sheen colour: gold stripes on white, 32 x 32; the sheen roughness (alpha): 0.3 and 0.8 checks
sheen_color = png_rgba(32, 32, lambda x, y: (255, 200, 90, 255) if (x // 4) % 2 else (255, 255, 255, 255))
sheen_rough = png_rgba(32, 32, lambda x, y: (255, 255, 255, 77 if ((x // 8) + (y // 8)) % 2 else 204))
white_sign = [1, 1, 1]
doc = {
    "asset": {"version": "2.0", "generator": "scenes/models/make_models.py (quasar)"},
    "extensionsUsed": ["KHR_materials_sheen", "KHR_materials_transmission", "KHR_materials_ior",
                       "KHR_materials_volume", "KHR_materials_emissive_strength"],
    "extensionsRequired": ["KHR_materials_sheen", "KHR_materials_transmission"],
    "scene": 0, "scenes": [{"nodes": list(range(len(meshes)))}],
    "nodes": [{"mesh": i, "name": m[0]} for i, m in enumerate(meshes)],
    "meshes": prims,
    "materials": [
        {"name": "ground", "pbrMetallicRoughness": {"baseColorFactor": [0.35, 0.35, 0.35, 1], "metallicFactor": 0}},
        {"name": "frame", "pbrMetallicRoughness": {"baseColorFactor": [0.08, 0.05, 0.03, 1], "metallicFactor": 0, "roughnessFactor": 0.5}},
        {"name": "velvet", "pbrMetallicRoughness": {"baseColorFactor": [0.25, 0.02, 0.05, 1], "metallicFactor": 0, "roughnessFactor": 0.9},
         "extensions": {"KHR_materials_sheen": {"sheenColorFactor": [1, 1, 1], "sheenColorTexture": {"index": 0},
                                                "sheenRoughnessFactor": 1, "sheenRoughnessTexture": {"index": 1}}}},
        {"name": "glass_clear", "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 0, "roughnessFactor": 0},
         "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1}, "KHR_materials_ior": {"ior": 1.5}}},
        {"name": "glass_frosted", "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 0, "roughnessFactor": 0.35},
         "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1}, "KHR_materials_ior": {"ior": 1.5}}},
        {"name": "glass_tinted", "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 0, "roughnessFactor": 0},
         "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1}, "KHR_materials_ior": {"ior": 1.5},
                        "KHR_materials_volume": {"thicknessFactor": 0.9, "attenuationDistance": 0.4,
                                                 "attenuationColor": [0.3, 0.6, 0.9]}}},
    ] + [{"name": "sign_%d" % s, "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0},
          "emissiveFactor": white_sign, "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": s}}}
         for s in (1, 4, 16)] + [
        {"name": "ceiling_panel", "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0},
         "emissiveFactor": [1, 0.95, 0.85], "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 40}}},
    ],
    "textures": [{"source": 0, "sampler": 0}, {"source": 1, "sampler": 0}],
    "samplers": [{"magFilter": 9728, "minFilter": 9728}],
    "images": [{"mimeType": "image/png", "uri": "data:image/png;base64," + base64.b64encode(im).decode()}
               for im in (sheen_color, sheen_rough)],
    "accessors": accessors, "bufferViews": views,
    "buffers": [{"byteLength": len(blob), "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
}
open('scenes/models/velvet-glass-and-signs.gltf', 'w').write(json.dumps(doc, indent=1) + '\n')
