#!/bin/sh
# SPDX-License-Identifier: MIT
#
# check-svg.sh FILE.svg COLOURS: FILE is well-formed XML (xmllint), renders
# to PNG (rsvg-convert), and the picture is not blank: at least COLOURS
# colours besides white and black and grey, and at least 0.3 % of the pixels
# not white (the PNG decoded with python3's zlib). Exit 0 or 1 with the reason.
set -eu
svg=$1
want=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
xmllint --noout "$svg" || { echo "check-svg: $svg is not well-formed XML" >&2; exit 1; }
rsvg-convert -f png -o "$tmp/out.png" "$svg" || { echo "check-svg: rsvg-convert failed on $svg" >&2; exit 1; }
python3 - "$tmp/out.png" "$want" <<'PY'
import struct, sys, zlib
data = open(sys.argv[1], 'rb').read()
assert data[:8] == b'\x89PNG\r\n\x1a\n', 'not a PNG'
pos, idat, w, h, bitdepth, ctype = 8, b'', 0, 0, 0, 0
while pos < len(data):
    n, kind = struct.unpack('>I4s', data[pos:pos + 8])
    body = data[pos + 8:pos + 8 + n]
    if kind == b'IHDR':
        w, h, bitdepth, ctype = struct.unpack('>IIBB', body[:10])
    elif kind == b'IDAT':
        idat += body
    pos += 12 + n
assert bitdepth == 8 and ctype in (2, 6), 'unexpected PNG type %d/%d' % (bitdepth, ctype)
bpp = 4 if ctype == 6 else 3
raw = zlib.decompress(idat)
stride = w * bpp
prev = bytearray(stride)
colours, inked = set(), 0
for y in range(h):
    f = raw[y * (stride + 1)]
    line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
    for i in range(stride):
        a = line[i - bpp] if i >= bpp else 0
        b = prev[i]
        c = prev[i - bpp] if i >= bpp else 0
        if f == 1: line[i] = (line[i] + a) & 255
        elif f == 2: line[i] = (line[i] + b) & 255
        elif f == 3: line[i] = (line[i] + (a + b) // 2) & 255
        elif f == 4:
            p = a + b - c
            pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
            line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
    for x in range(w):
        px = tuple(line[x * bpp:x * bpp + 3])
        alpha = line[x * bpp + 3] if bpp == 4 else 255
        if alpha and px != (255, 255, 255):
            inked += 1
            if max(px) - min(px) > 60:  # a colour, not a grey
                colours.add((px[0] >> 4, px[1] >> 4, px[2] >> 4))
    prev = line
share = inked / float(w * h)
if share < 0.003 or len(colours) < int(sys.argv[2]):
    sys.exit('check-svg: blank picture: %.2f %% inked, %d colours (want %s)' % (share * 100, len(colours), sys.argv[2]))
print('check-svg: %dx%d, %.2f %% inked, %d colours' % (w, h, share * 100, len(colours)))
PY
