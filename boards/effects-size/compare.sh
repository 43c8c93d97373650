#!/bin/sh
# Builds the firmware images (thumbv7em-none-eabihf, release) and compares
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
  echo "Four firmware images (\`boards/effects-size\`, thumbv7em-none-eabihf, release, fat"
  echo "LTO) draw the same tetrahedron; \`diffuse\` picks \`NoSpecular\`, \`NoDepth\`,"
  echo "Gouraud; \`specular\` differs from \`diffuse\` only by \`BlinnExact\` (the"
  echo "specular term); \`two-sided\` differs from \`specular\` only by"
  echo "\`TwoSided<BlinnExact>\` (two-sided lighting); \`full\` picks \`BlinnExact\`,"
  echo "\`DepthTest\`, Phong. Made by"
  echo "\`boards/effects-size/compare.sh\` (\`llvm-size\` and \`llvm-nm\` of llvm-tools)."
  echo
  echo '```text'
  "$BIN/llvm-size" "$ELF/diffuse" "$ELF/specular" "$ELF/two-sided" "$ELF/full"
  echo '```'
  echo
  echo "Symbols of the specular power, the Phong fill, the depth test and the back"
  echo "faces' lighting in each image (\`llvm-nm -C --size-sort\`, matching"
  echo "\`pow_q30|phong|exp2|log2|depth|light_back|clip_fan_sided\`):"
  echo
  for b in diffuse specular two-sided full; do
    echo "\`$b\`:"
    echo
    echo '```text'
    "$BIN/llvm-nm" -C --size-sort "$ELF/$b" | grep -Ei 'pow_q30|phong|exp2|log2|depth|light_back|clip_fan_sided' || echo "(none)"
    echo '```'
    echo
  done
} > size.md
cat size.md
