# make_corpus.py - maintenance only (never run by make): rebuilds the hand-made and broken files of
# tests/corpus from tests/corpus/ok-golden.pvs after a format change. python3 tests/make_corpus.py
# (formats 2 to 4: the baked ok-* files were converted from the previous format by decoding with the old
# reader and encoding with the new writer, tables unchanged; tests/golden/v1.pvs and v2.pvs stay to test the
# re-bake message)
import zlib, struct
d='tests/corpus'
def al(n): return (n+7)&~7
def build(secs):
    pos=al(32+16*len(secs)); offs=[]
    for t,dd in secs: offs.append(pos); pos=al(pos+len(dd))
    f=bytearray(pos); f[0:4]=b'PVS\x1a'; struct.pack_into('<IIII',f,4,4,pos,len(secs),0)
    for i,(t,dd) in enumerate(secs):
        f[offs[i]:offs[i]+len(dd)]=dd
        struct.pack_into('<4sIII',f,32+16*i,t,offs[i],len(dd),zlib.crc32(dd)&0xffffffff)
    struct.pack_into('<I',f,20,zlib.crc32(bytes(f[0:20])+bytes(f[32:32+16*len(secs)]))&0xffffffff)
    return bytes(f)
modl=struct.pack('<II',88,0)+struct.pack('<88H',*([2048]*88)) # identity order, even odds
good=open(d+'/ok-golden.pvs','rb').read()
def fix(b):
    b=bytearray(b); n=struct.unpack_from('<I',b,12)[0]
    for i in range(n):
        t,o,s,c=struct.unpack_from('<IIII',b,32+16*i)
        if o+s<=len(b): struct.pack_into('<I',b,32+16*i+12,zlib.crc32(bytes(b[o:o+s]))&0xffffffff)
    struct.pack_into('<I',b,20,zlib.crc32(bytes(b[0:20])+bytes(b[32:32+16*n]))&0xffffffff)
    return bytes(b)
def sec(b,tag):
    n=struct.unpack_from('<I',b,12)[0]
    for i in range(n):
        t,o,s,c=struct.unpack_from('<4sIII',b,32+16*i)
        if t==tag: return o,s
out={}
out['bad-truncated']=good[:len(good)//2]
out['bad-empty']=b''
out['bad-magic']=b'PVX'+good[3:]
b=bytearray(good); b[100]^=1; out['bad-checksum']=bytes(b)
m,_=sec(good,b'META'); b=bytearray(good); struct.pack_into('<I',b,m+20,1); out['bad-chain-bound']=fix(b)
t,_=sec(good,b'TREE'); b=bytearray(good); struct.pack_into('<I',b,t+8,0x7fc00000); out['bad-tree']=fix(b)
def records(b):
    r,_=sec(b,b'RECS'); cells=struct.unpack_from('<I',b,sec(b,b'META')[0])[0]; out=[]
    for blk in range((cells+15)//16):
        p=r+struct.unpack_from('<I',b,r+4*blk)[0]
        for c in range(16*blk,min(cells,16*blk+16)):
            R=b[p]; z=b[p+1]; assert R<128 and z<128; out.append((p+1,c-(z>>1 if z%2==0 else -((z+1)>>1)) if z else None)); p+=1+R
    return out
# a cycle: key cell j made a delta of a cell i whose base is j (META's key count one less, so the chain rule decides)
b=bytearray(good); rs=records(b)
i,j=next((i,base) for i,(at,base) in enumerate(rs) if base is not None and rs[base][1] is None and abs(i-base)<60)
b[rs[j][0]]=2*(j-i) if j>=i else 2*(i-j)-1; m,_=sec(b,b'META'); struct.pack_into('<I',b,m+24,struct.unpack_from('<I',b,m+24)[0]-1)
out['bad-cycle']=fix(b)
c,_=sec(good,b'CELL'); b=bytearray(good); g=struct.unpack_from('<I',b,c+24)[0]
if g&255==255: struct.pack_into('<I',b,c+44,0x7fc00000) # table 0 of floats: a NaN
else: struct.pack_into('<I',b,c+24,(g&255)|0x7fff<<8) # table 0's grid step 2^32767: coordinates not finite
out['bad-cell-nan']=fix(b)
b=bytearray(good); struct.pack_into('<I',b,4,5); out['bad-version']=bytes(b)
for k,v in out.items(): open(d+'/'+k+'.pvs','wb').write(v)

# a billion cells whose indices are all 0 bits wide: must be rejected in time linear in its 360 bytes
meta=struct.pack('<IIIfIIII',0x3fffffff,10,1,0.0,1,8,1,0)
cell=struct.pack('<III',1,1,1)+bytes([0,0,0,0,0,0,0,0])+struct.pack('<6I',0,0,0,0,0,0) # tables: one 0 each, 0 bits
tree=struct.pack('<II',0,1)+bytes([2,0]) # depth 0, 1-bit leaf offsets 0 and 1, the item 0
recs=struct.pack('<II',8,10)+bytes([1,0])
open(d+'/bad-huge-cell-count.pvs','wb').write(build([(b'META',meta),(b'CELL',cell),(b'TREE',tree),(b'RECS',recs),(b'MODL',modl)]))
# an empty unknown section at the offset of TREE, listed after it: opens (sections of size 0 are fine)
g=bytearray(good); n=struct.unpack_from('<I',g,12)[0]
secs=[]
for i in range(n):
    t,o,s,c=struct.unpack_from('<4sIII',g,32+16*i); secs.append((t,bytes(g[o:o+s])))
secs.append((b'ZERO',b''))
open(d+'/ok-empty-section.pvs','wb').write(build(secs))

# virtual occluders (VOCC, >>vocc): the golden file plus a VOCC section, and broken variants
def vocc_sec(cells, counts, scales, occ, flags=0, base=0.0, step=0.25, first=None):
    blocks=(cells+15)//16; n=sum(counts)
    if first is None:
        first=[0]
        for b in range(blocks): first.append(first[-1]+sum(counts[16*b:16*b+16]))
    return struct.pack('<IIff',flags,n,base,step)+struct.pack('<%dI'%(blocks+1),*first)+bytes(counts)+bytes(scales)+bytes(occ)
def with_vocc(sec_bytes):
    secs=[]
    for i in range(struct.unpack_from('<I',good,12)[0]):
        t,o,s,c=struct.unpack_from('<4sIII',good,32+16*i); secs.append((t,bytes(good[o:o+s])))
    secs.append((b'VOCC',sec_bytes))
    return build(secs)
m,_=sec(good,b'META'); cells=struct.unpack_from('<I',good,m)[0]
counts=[(i*5)%4 for i in range(cells)]; scales=[120+(i%40) for i in range(cells)]
occ=[]
for i in range(sum(counts)): occ+=[(37*i+11)%256,(53*i+7)%256,(71*i+200)%256,(13*i+90)%256,1+(i%200)]
open(d+'/ok-vocc.pvs','wb').write(with_vocc(vocc_sec(cells,counts,scales,occ)))
open(d+'/ok-vocc-only.pvs','wb').write(with_vocc(vocc_sec(cells,counts,scales,occ,flags=1)))
open(d+'/bad-vocc-flags.pvs','wb').write(with_vocc(vocc_sec(cells,counts,scales,occ,flags=6)))
open(d+'/bad-vocc-step.pvs','wb').write(with_vocc(vocc_sec(cells,counts,scales,occ,step=float('nan'))))
bad=list(counts); bad[0]+=1
open(d+'/bad-vocc-count.pvs','wb').write(with_vocc(vocc_sec(cells,bad,scales,occ)))
open(d+'/bad-vocc-size.pvs','wb').write(with_vocc(vocc_sec(cells,counts,scales,occ)+b'\0\0\0'))
fb=[0]
for b in range((cells+15)//16): fb.append(fb[-1]+sum(counts[16*b:16*b+16]))
fb[1]+=1
open(d+'/bad-vocc-block.pvs','wb').write(with_vocc(vocc_sec(cells,counts,scales,occ,first=fb)))
# an object order naming object 120 of 100 (META says 100 objects, MODL orders them in 7 bits)
secs=[]
for i in range(struct.unpack_from('<I',good,12)[0]):
    t,o,s_,c=struct.unpack_from('<4sIII',good,32+16*i); secs.append([t,bytearray(good[o:o+s_])])
for sc in secs:
    if sc[0]==b'META': struct.pack_into('<I',sc[1],4,100)
    if sc[0]==b'MODL':
        ids=list(range(99))+[120]; v=0
        for k,x in enumerate(ids): v|=x<<(7*k)
        sc[1]=bytearray(sc[1][:8])+sc[1][8:184]; struct.pack_into('<I',sc[1],4,7); sc[1]+=v.to_bytes((700+7)//8,'little')
open(d+'/bad-object-range.pvs','wb').write(build([(t,bytes(x)) for t,x in secs]))
