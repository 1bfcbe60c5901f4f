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
