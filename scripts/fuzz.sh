#!/usr/bin/env bash
# Bounded fuzz run of every libFuzzer target in build-asan/ (built by scripts/sanitize.sh):
# a fixed number of runs per target (RUNS below; FUZZ_RUNS overrides) with a fixed seed, capped at
# FUZZ_SECONDS (default 60) each, seeded from the golden files and presets.
# A crash, sanitizer report, leak, timeout or out-of-memory fails the run; the reproducer is left
# in build-asan/fuzz-artifacts/. Usage: bash scripts/fuzz.sh [target ...]
set -euo pipefail
cd "$(dirname "$0")/.."
B=build-asan
T="${FUZZ_SECONDS:-60}"
[ -x "$B/fuzz/fuzz_ktx2" ] || bash scripts/sanitize.sh --build-only
export ASAN_OPTIONS="detect_leaks=1:halt_on_error=1:intercept_tls_get_addr=0"  # as scripts/sanitize.sh
export LSAN_OPTIONS="suppressions=$PWD/fuzz/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
corpus="$B/fuzz-corpus"
rm -rf "$corpus"
mkdir -p "$B/fuzz-artifacts"
seed() {  # seed TARGET FILES...
  local t=$1; shift
  mkdir -p "$corpus/$t"
  for f in "$@"; do [ -f "$f" ] && cp "$f" "$corpus/$t/"; done
  return 0
}
seed ktx2 golden/expected/*.ktx2
seed dds golden/expected/*.dds
seed manifest $(ls golden/expected/*.json | grep -v report)
seed layout formats/bakers/*.json
seed blocks golden/expected/*.iz.*
seed report golden/expected/*.report.json
# The intermediate EXR of a golden input; small meshes (byte 0 picks .obj / .gltf / .glb).
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
A="$B/ahdpack"; [ -x "$A" ] || A=build/ahdpack
ASAN_OPTIONS=detect_leaks=0 "$A" convert golden/inputs/scene13_l1_seed3.exr -o "$tmp/x.ktx2" --keep-intermediate -q
seed intermediate "$tmp/x.ahd.exr"
mkdir -p "$corpus/mesh"
printf '\000v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvt 1 1\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1\nf 2/2/1 4/4/1 3/3/1\n' >"$corpus/mesh/quad.obj"
printf '\000o a\nv 0 0 0\nv 2 0 0\nv 0 2 1\nvt 0 0\nvt 1 0\nvt 0 1\nvt 0.5 0.5\nf 1/1 2/2 3/3\ng b\nf 1/4 2/2 3/1\n' >"$corpus/mesh/two.obj"
# Issue 26's readers: images (byte 0: 0 .png, 1 .tga, 2 .hdr, 3 .exr), Godot side files (byte 0:
# 0 .exr.import, 1 .lmbake, 2 version string), placements (Unity YAML / JSON), profiles.
mkdir -p "$corpus/image" "$corpus/godot" "$corpus/placement"
# TGA: uncompressed 2x2 RGB; HDR: flat 2x2 RGBE.
{ printf '\001'; printf '\000\000\002\000\000\000\000\000\000\000\000\000\002\000\002\000\030\000'; printf '\377\000\000\000\377\000\000\000\377\177\177\177'; } >"$corpus/image/rgb.tga"
{ printf '\002'; printf '#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 2\n'; printf '\200\200\200\201\100\100\100\202\200\000\000\201\000\200\000\201'; } >"$corpus/image/flat.hdr"
for f in golden/inputs/*.exr; do [ -f "$f" ] && { printf '\003'; cat "$f"; } >"$corpus/image/$(basename "$f")" && break; done
if command -v python3 >/dev/null; then  # PNG: 2x2 RGBA, zlib-compressed
  python3 -c 'import struct,zlib,sys
def ch(t,d): return struct.pack(">I",len(d))+t+d+struct.pack(">I",zlib.crc32(t+d)&0xffffffff)
raw=b"".join(b"\x00"+b"\x80\x40\x20\xff"*2 for _ in range(2))
sys.stdout.buffer.write(b"\x00\x89PNG\r\n\x1a\n"+ch(b"IHDR",struct.pack(">IIBBBBB",2,2,8,6,0,0,0))+ch(b"IDAT",zlib.compress(raw))+ch(b"IEND",b""))' >"$corpus/image/rgba.png"
fi
printf '\000[remap]\nimporter="2d_array_texture"\n\n[params]\nslices/vertical=4\nslices/horizontal=1\n' >"$corpus/godot/lm.exr.import"
printf '\001RSRC\000\000\000\000\030\000\000\000_uses_packed_directional\000light_texture\000' >"$corpus/godot/lm.lmbake"
printf '\0024.4' >"$corpus/godot/version"
printf '%%YAML 1.1\n--- !u!1 &100\nGameObject:\n  m_Name: Cube\n--- !u!23 &200\nMeshRenderer:\n  m_GameObject: {fileID: 100}\n  m_LightmapIndex: 0\n  m_LightmapTilingOffset: {x: 0.5, y: 0.5, z: 0.25, w: 0}\n' >"$corpus/placement/scene.unity"
printf '{"placements": [{"node": "Cube", "page": 0, "scale": [0.5, 0.5], "offset": [0.25, 0]}]}' >"$corpus/placement/p.json"
seed profile formats/profiles/*.json
# ArrayMesh resources (byte 0: 0 a `_surfaces` value, 1 a .tres/.res/.mesh, 2 a .tscn's inline mesh
# "A"): a one-triangle surface, and Godot's own files when the generated fixtures are present.
mkdir -p "$corpus/godot_mesh"
printf '\000[{"aabb": AABB(0, 0, 0, 1, 1, 1), "attribute_data": PackedByteArray(0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 128, 63, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 128, 63), "format": 34359738401, "primitive": 3, "vertex_count": 3, "vertex_data": PackedByteArray("AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA")}]' >"$corpus/godot_mesh/triangle"
for f in tests/data/godot/generated/arraymesh_*; do [ -f "$f" ] && { printf '\001'; cat "$f"; } >"$corpus/godot_mesh/$(basename "$f")"; done
# Issue 44's readers. Godot scene files (byte 0: 0 .tscn, 1 .lmbake, 2 .res/.mesh, 3 .obj); the
# small unwrap caches of the real bake; job files; KTX2/DDS lightmaps read as input images (the
# golden planes and a zstd-supercompressed one); the cache's entry (byte 0 even) and inputs record
# (byte 0 = 3: its hash recomputed by the target) of a cached conversion.
mkdir -p "$corpus/godot_scene" "$corpus/jobs" "$corpus/cache"
i=0
for f in tests/data/godot/generated/*.tscn tests/data/godot/corpus/*/*/*.tscn tests/data/godot/corpus/*/*.tscn; do
  [ -f "$f" ] && [ "$(stat -c %s "$f")" -lt 65536 ] && { printf '\000'; cat "$f"; } >"$corpus/godot_scene/tscn$((i++))"
done
for f in tests/data/godot/generated/*.lmbake tests/data/godot/corpus/*/*/*.lmbake tests/data/godot/corpus/*/*.lmbake; do
  [ -f "$f" ] && [ "$(stat -c %s "$f")" -lt 65536 ] && { printf '\001'; cat "$f"; } >"$corpus/godot_scene/lmbake$((i++))"
done
for f in tests/data/godot/generated/arraymesh_*.res tests/data/godot/generated/arraymesh_*.mesh; do
  [ -f "$f" ] && { printf '\002'; cat "$f"; } >"$corpus/godot_scene/res$((i++))"
done
printf '\003o a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1\nusemtl m\nf 3/3/1 2/2/1 1/1/1\n' >"$corpus/godot_scene/tri.obj"
seed unwrap_cache $(find tests/data/bakes -name '*.unwrap_cache' -size -4k 2>/dev/null | sort | head -8)
seed jobs tests/data/bevy/cornell.jobs.json
printf '{"jobs": [{"input": "a.exr", "mesh": "m.glb", "node": "n", "uv-set": 1, "output": "a"}, {"input": "b.ktx2", "allow-mismatch": true}]}' >"$corpus/jobs/two.json"
seed texture golden/expected/*.ktx2 golden/expected/*.dds
ASAN_OPTIONS=detect_leaks=0 "$A" convert golden/inputs/scene13_l1_seed3.exr -o "$tmp/z/z.ktx2" --zstd -q
seed texture "$tmp"/z/z.iz.*.ktx2
ASAN_OPTIONS=detect_leaks=0 "$A" convert golden/inputs/scene13_l1_seed3.exr -o "$tmp/c/c.ktx2" --cache "$tmp/cache" -q
for f in "$tmp"/cache/*.ahdcache; do [ -f "$f" ] && { printf '\000'; cat "$f"; } >"$corpus/cache/entry"; done
for f in "$tmp"/cache/*.ahdinputs; do [ -f "$f" ] && { printf '\003'; cat "$f"; } >"$corpus/cache/inputs"; done
failed=0
# A fixed number of runs per target with a fixed seed: the same inputs are tried on every machine,
# so a run that passed here passes in CI (FUZZ_SECONDS only caps the time on a slow machine, which
# then tries a prefix of the same sequence). About 15 s each on this 2-core machine (CI's budget:
# the whole of .ci/run stays well under 30 minutes; a longer run is FUZZ_RUNS=… FUZZ_SECONDS=…).
declare -A RUNS=([ktx2]=300000 [dds]=500000 [manifest]=50000 [layout]=30000 [intermediate]=250 [blocks]=30000 [mesh]=150
                [image]=1500 [godot]=50000 [placement]=25000 [profile]=25000 [report]=25000 [godot_mesh]=50000
                [godot_scene]=50000 [unwrap_cache]=100000 [jobs]=25000 [texture]=50000 [cache]=50000)
# The issue-26 targets are capped at 12 s each (and every target at FUZZ_SECONDS: .ci/run's budget).
declare -A SECONDS_CAP=([image]=12 [godot]=12 [placement]=12 [profile]=12 [report]=12 [godot_mesh]=12)
for t in ${@:-ktx2 dds manifest layout intermediate blocks mesh image godot placement profile report godot_mesh \
              godot_scene unwrap_cache jobs texture cache}; do
  extra=(-runs="${FUZZ_RUNS:-${RUNS[$t]}}")
  cap="${SECONDS_CAP[$t]:-$T}"; [ "$cap" -gt "$T" ] && cap="$T"
  # OpenEXR and Assimp are not instrumented and keep caches of their own: leaks are only ours to find elsewhere.
  # (Their exit-time check too: OpenImageIO keeps per-thread error strings it never frees.)
  asan="$ASAN_OPTIONS"
  case $t in intermediate|mesh|image) extra+=(-detect_leaks=0); asan="detect_leaks=0:halt_on_error=1" ;; esac
  if ! ASAN_OPTIONS="$asan" "$B/fuzz/fuzz_$t" "$corpus/$t" -max_total_time="$cap" -seed=1 -timeout=10 -rss_limit_mb=2048 \
      -malloc_limit_mb=1024 -artifact_prefix="$B/fuzz-artifacts/$t-" -print_final_stats=1 "${extra[@]}" \
      >"$B/fuzz-artifacts/$t.log" 2>&1; then
    echo "fuzz: $t FAILED (see $B/fuzz-artifacts/$t.log)"; tail -30 "$B/fuzz-artifacts/$t.log"; failed=1
  else
    echo "fuzz: $t ok ($(grep -o 'stat::number_of_executed_units: *[0-9]*' "$B/fuzz-artifacts/$t.log" | grep -o '[0-9]*$') runs)"
  fi
done
exit $failed
