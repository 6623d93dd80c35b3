#!/usr/bin/env bash
# Regenerates golden/ ON PURPOSE (after a deliberate change of the output bytes or error figures).
# Review `git diff golden/` before committing: every changed byte is a changed output.
set -euo pipefail
cd "$(dirname "$0")/.."
A=./build/ahdpack
[ -x "$A" ] || bash scripts/build.sh
rm -rf golden/inputs golden/expected
mkdir -p golden/inputs golden/expected
"$A" sample --size 16 --order 2 --seed 0 -o golden/inputs/scene16_l2.exr >/dev/null
"$A" sample --size 13 --order 1 --seed 3 -o golden/inputs/scene13_l1_seed3.exr >/dev/null
"$A" sample --size 24 --order 2 --seed 5 -o golden/inputs/scene24_l2_seed5.exr >/dev/null
while IFS=' ' read -r name input profile container; do
  [ -z "$name" ] && continue
  "$A" convert "golden/inputs/$input" -o "golden/expected/$name.$container" --profile "$profile" --threads 1 --measure full -q
done < golden/cases.txt
echo "golden/ regenerated: $(ls golden/expected | wc -l) files"
