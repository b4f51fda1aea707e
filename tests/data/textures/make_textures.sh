#!/bin/sh
# Makes the textures the reference tests read (ImageMagick's `convert`):
# red.jpg, an 8 × 8 JPEG of one red (#e01010), for decoding JPEG base-colour textures.
cd "$(dirname "$0")" && convert -size 8x8 xc:'#e01010' -quality 95 red.jpg
