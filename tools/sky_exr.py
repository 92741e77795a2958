#!/usr/bin/env python3
"""Writes a 256x128 equirectangular sky as an uncompressed float OpenEXR (standard library only):
a blue gradient above the horizon, warm grey ground, a 5-degree sun 35 degrees up (radiance ~900).
Usage: python3 tools/sky_exr.py OUT.exr   (docs/scenes/environment.json expects sky.exr beside it)
"""
import struct, math
W,H=256,128
def le(v,n): return v.to_bytes(n,'little')
def attr(name,typ,val): return name.encode()+b'\0'+typ.encode()+b'\0'+le(len(val),4)+val
names=['B','G','R']
ch=b''.join(n.encode()+b'\0'+le(2,4)+le(0,4)+le(1,4)+le(1,4) for n in names)+b'\0'
box=b''.join(le(v,4) for v in [0,0,W-1,H-1])
hdr=b'\x76\x2f\x31\x01'+le(2,4)+attr('channels','chlist',ch)+attr('compression','compression',b'\0')+attr('dataWindow','box2i',box)+attr('displayWindow','box2i',box)+attr('lineOrder','lineOrder',b'\0')+attr('pixelAspectRatio','float',struct.pack('<f',1))+attr('screenWindowCenter','v2f',struct.pack('<ff',0,0))+attr('screenWindowWidth','float',struct.pack('<f',1))+b'\0'
sun=(math.radians(35), math.radians(60))  # elevation, azimuth
sd=(math.cos(sun[0])*math.sin(sun[1]), math.sin(sun[0]), -math.cos(sun[0])*math.cos(sun[1]))
rows=[]
for y in range(H):
    th=(y+0.5)/H*math.pi
    R=[];G=[];B=[]
    for x in range(W):
        ph=(x+0.5)/W*2*math.pi
        d=(math.sin(th)*math.sin(ph), math.cos(th), -math.sin(th)*math.cos(ph))
        if d[1]>0:
            t=d[1]; r,g,b=0.35+0.25*(1-t),0.55+0.2*(1-t),0.95
        else:
            r,g,b=0.25,0.22,0.2
        c=sum(a*b_ for a,b_ in zip(d,sd))
        if c>math.cos(math.radians(2.5)): r,g,b=900,820,700
        R.append(r);G.append(g);B.append(b)
    rows.append((B,G,R))
line=8+W*3*4
first=len(hdr)+H*8
out=bytearray(hdr)
for y in range(H): out+=le(first+y*line,8)
for y in range(H):
    out+=le(y,4)+le(line-8,4)
    for p in rows[y]: out+=struct.pack('<%df'%W,*p)
import sys
open(sys.argv[1] if len(sys.argv) > 1 else 'sky.exr','wb').write(out)
