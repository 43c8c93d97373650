#!/bin/sh
# Builds the two firmware images (thumbv7em-none-eabihf, release) and compares
# their sizes and symbols; writes size.md next to this script, which
# `fixshade effects` includes in docs/effects.md.
set -eu
cd "$(dirname "$0")"
rustup component add llvm-tools >/dev/null 2>&1 || true
cargo build --release --bins "$@"
BIN=$(rustc --print sysroot)/lib/rustlib/$(rustc -vV | sed -n 's/^host: //p')/bin
ELF=target/thumbv7em-none-eabihf/release
{
  echo "## Unused effects are not linked"
  echo
  echo "Two firmware images (\`boards/effects-size\`, thumbv7em-none-eabihf, release, fat"
  echo "LTO) draw the same tetrahedron; \`diffuse\` picks \`NoSpecular\`, \`NoDepth\`,"
  echo "Gouraud; \`specular\` differs from \`diffuse\` only by \`BlinnExact\` (the"
  echo "specular term); \`full\` picks \`BlinnExact\`, \`DepthTest\`, Phong. Made by"
  echo "\`boards/effects-size/compare.sh\` (\`llvm-size\` and \`llvm-nm\` of llvm-tools)."
  echo
  echo '```text'
  "$BIN/llvm-size" "$ELF/diffuse" "$ELF/specular" "$ELF/full"
  echo '```'
  echo
  echo "Symbols of the specular power, the Phong fill and the depth test in each"
  echo "image (\`llvm-nm -C --size-sort\`, matching \`pow_q30|phong|exp2|log2|depth\`):"
  echo
  for b in diffuse specular full; do
    echo "\`$b\`:"
    echo
    echo '```text'
    "$BIN/llvm-nm" -C --size-sort "$ELF/$b" | grep -Ei 'pow_q30|phong|exp2|log2|depth' || echo "(none)"
    echo '```'
    echo
  done
} > size.md
cat size.md
