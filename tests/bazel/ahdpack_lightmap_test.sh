#!/usr/bin/env bash
# The Bazel rule (bazel/ahdpack.bzl ahdpack_lightmap) with a remote cache: Debian's bazel-bootstrap,
# offline, and nginx with WebDAV PUT on 127.0.0.1 as Bazel's HTTP remote cache. A workspace of
# four lightmaps — three EXRs (golden/inputs) and a Godot project (tests/data/godot/corpus/gltf:
# its .exr.import, .lmbake, project.godot, scene and glTF models declared) — is built in checkout A;
# a copy at another path (checkout B, so another output base) then builds every lightmap from the
# remote cache (4 remote cache hits, no action run) with byte-identical outputs; replacing one
# input of B rebuilds only that lightmap.
# Usage: ahdpack_lightmap_test.sh AHDPACK_EXE SOURCE_DIR. Exit 77 (skipped) without bazel or nginx.
set -euo pipefail
cli="$1"; src="$2"
command -v bazel >/dev/null || { echo "skipped: bazel not found (scripts/setup.sh installs bazel-bootstrap)"; exit 77; }
nginx=""; for n in /usr/sbin/nginx /usr/bin/nginx; do [ -x "$n" ] && nginx="$n" && break; done
[ -n "$nginx" ] || { echo "skipped: nginx not found (scripts/setup.sh installs nginx-light)"; exit 77; }

tmp="$(mktemp -d /tmp/ahdpack-bazel.XXXXXX)"
nginx_pid=""
cleanup() {
  for ws in "$tmp/a" "$tmp/b"; do
    [ -d "$ws" ] && (cd "$ws" && bazel --output_user_root="$tmp/root" shutdown >/dev/null 2>&1 || true)
  done
  [ -n "$nginx_pid" ] && kill "$nginx_pid" 2>/dev/null && wait "$nginx_pid" 2>/dev/null
  chmod -R u+w "$tmp" 2>/dev/null; rm -rf "$tmp"
}
trap cleanup EXIT
t0=$SECONDS

# The remote cache: nginx in the foreground on a free port, serving $tmp/cache with PUT.
port="$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')"
mkdir -p "$tmp/cache" "$tmp/nginx/body"
cat > "$tmp/nginx/nginx.conf" <<CONF
daemon off; master_process off; worker_processes 1;
pid $tmp/nginx/nginx.pid; error_log $tmp/nginx/error.log;
events { worker_connections 64; }
http {
  access_log $tmp/nginx/access.log;
  client_body_temp_path $tmp/nginx/body; client_max_body_size 0;
  server {
    listen 127.0.0.1:$port; root $tmp/cache;
    location / { dav_methods PUT; create_full_put_path on; dav_access user:rw; }
  }
}
CONF
"$nginx" -p "$tmp/nginx/" -c "$tmp/nginx/nginx.conf" -e "$tmp/nginx/error.log" & nginx_pid=$!
for _ in $(seq 100); do (exec 3<>/dev/tcp/127.0.0.1/$port) 2>/dev/null && break; sleep 0.1; done
(exec 3<>/dev/tcp/127.0.0.1/$port) 2>/dev/null || { echo "FAIL: nginx did not start"; cat "$tmp/nginx/error.log"; exit 1; }

# Checkout A: the rule, the tool and its data as declared inputs, three lightmaps.
a="$tmp/a"; mkdir -p "$a/tools" "$a/maps"
touch "$a/WORKSPACE"
cp "$src/bazel/ahdpack.bzl" "$a/tools/"
cp "$cli" "$a/tools/ahdpack"
cp "$(dirname "$cli")"/libahd_*.so "$a/tools/"   # the modules: Assimp opens the Godot project's meshes
cp -r "$src/formats" "$a/tools/formats"
cat > "$a/tools/BUILD" <<'B'
exports_files(["ahdpack"])
filegroup(name = "ahdpack_modules", srcs = glob(["libahd_*.so"]), visibility = ["//visibility:public"])
filegroup(name = "ahdpack_formats", srcs = glob(["formats/**"]), visibility = ["//visibility:public"])
B
cp "$src/golden/inputs/scene13_l1_seed3.exr" "$a/maps/one.exr"
cp "$src/golden/inputs/scene16_l2.exr" "$a/maps/two.exr"
cp "$src/golden/inputs/scene24_l2_seed5.exr" "$a/maps/three.exr"
cp -r "$src/tests/data/godot/corpus/gltf" "$a/maps/godot"
cat > "$a/maps/BUILD" <<'B'
load("//tools:ahdpack.bzl", "ahdpack_lightmap")
[ahdpack_lightmap(name = n, src = n + ".exr", profile = "pc-bc") for n in ["one", "two", "three"]]
ahdpack_lightmap(name = "world", src = "godot/world.exr", srcs = glob(["godot/**"], exclude = ["godot/world.exr"]))
B
cp -r "$a" "$tmp/b"   # checkout B: the same files at another path

build() {  # build WORKSPACE LOG (then prints its summary line)
  (cd "$1" && nice bazel --output_user_root="$tmp/root" --max_idle_secs=120 build //maps:all \
     --remote_cache="http://127.0.0.1:$port/bazel/" --noshow_progress --color=no --curses=no \
     --experimental_ui_max_stdouterr_bytes=100000 > "$2" 2>&1) || { echo "FAIL: bazel build in $1:"; cat "$2"; exit 1; }
}
summary() { grep "processes:" "$1" | tail -1; }
digests() { (cd "$1/bazel-bin/maps" && find one two three world -type f | sort | xargs sha256sum); }

build "$a" "$tmp/a1.log"; echo "A: $(summary "$tmp/a1.log")"
summary "$tmp/a1.log" | grep -q "remote cache hit" && { echo "FAIL: A's first build hit a cache that was empty"; exit 1; }
[ "$(digests "$a" | grep -c '\.json$')" = 8 ] || { echo "FAIL: A did not write 4 manifests + 4 reports"; digests "$a"; exit 1; }
echo "after A: $((SECONDS - t0)) s"

build "$tmp/b" "$tmp/b1.log"; echo "B: $(summary "$tmp/b1.log")"
summary "$tmp/b1.log" | grep -Eq ": 4 remote cache hit" || { echo "FAIL: B is not 4 remote cache hits"; cat "$tmp/b1.log"; exit 1; }
summary "$tmp/b1.log" | grep -Eq "linux-sandbox|local|processwrapper" && { echo "FAIL: B ran an action"; exit 1; }
diff <(digests "$a") <(digests "$tmp/b") || { echo "FAIL: B's outputs differ from A's"; exit 1; }
echo "B: the same bytes as A ($(digests "$a" | wc -l) files)"
echo "after B: $((SECONDS - t0)) s"

before="$(digests "$tmp/b")"
cp "$src/golden/inputs/scene16_l2.exr" "$tmp/b/maps/one.exr"   # one's input replaced
build "$tmp/b" "$tmp/b2.log"; echo "B after replacing one.exr: $(summary "$tmp/b2.log")"
summary "$tmp/b2.log" | grep -Eq ": 2 processes: 1 internal, 1 (linux-sandbox|local|processwrapper-sandbox)" ||
  { echo "FAIL: not exactly one action run"; cat "$tmp/b2.log"; exit 1; }
after="$(digests "$tmp/b")"
[ "$(diff <(echo "$before" | grep -v ' one/') <(echo "$after" | grep -v ' one/') | wc -l)" = 0 ] ||
  { echo "FAIL: two or three changed"; exit 1; }
[ "$(echo "$before" | grep ' one/one\.json$')" != "$(echo "$after" | grep ' one/one\.json$')" ] ||
  { echo "FAIL: one's manifest did not change"; exit 1; }
echo "only one rebuilt; total $((SECONDS - t0)) s"
