"""ahdpack_lightmap: one lightmap converted by ahdpack as a Bazel action.

Copy this file into your workspace (say tools/ahdpack.bzl) beside the ahdpack executable, its
modules (libahd_*.so) and its data folder, or reach it through a local_repository; docs/asset-cook.md "Bazel: ahdpack_lightmap"
describes the setup, the remote cache and what to declare. Tested with Debian's bazel-bootstrap 4.2.3
by tests/bazel/ahdpack_lightmap_test.sh (test Bazel.AhdpackLightmapRemoteCache).

    load("//tools:ahdpack.bzl", "ahdpack_lightmap")
    ahdpack_lightmap(
        name = "world",
        src = "levels/world.exr",                  # what `ahdpack convert` is given
        srcs = ["levels/world.exr.import", "levels/world.lmbake", "project.godot"],
        profile = "pc-bc",
    )

The output is a directory, <package>/<name>/, holding <name>.json (the manifest), the planes it
names (<name>.<plane>.<hash>.<ext>, content-addressed, so their names are only known after the
conversion) and <name>.report.json (which carries seconds: the one non-deterministic file).
"""

def _formats_dir(files):
    # The folder holding profiles/ and bakers/: what AHD_FORMATS_DIR names (src/files/paths.h).
    for f in files:
        i = f.path.rfind("/formats/")
        if i >= 0:
            return f.path[:i + len("/formats")]
        if f.path.startswith("formats/"):
            return "formats"
    fail("ahdpack_lightmap: `formats` must hold the files of ahdpack's formats/ folder")

# Runs in the action: copies the declared inputs (arguments up to "--") into a scratch tree as real
# files, then runs ahdpack there. Bazel's sandbox gives an action its inputs as symlinks into the
# source tree, and the Godot reader refuses a project file whose symlink leads out of the project
# (src/bakers/godot/godot_scene.cpp: a symlink leading out is an attack it blocks), so a Godot set
# read through the sandbox's symlinks would fail; copies are inside. Everything else is the same
# bytes either way.
_RUN = """set -eu
tool="$PWD/$1"; out="$PWD/$2"; shift 2
scratch="$(mktemp -d "${TMPDIR:-/tmp}/ahdpack_lightmap.XXXXXX")"
trap 'rm -rf "$scratch"' EXIT
while [ "$1" != "--" ]; do mkdir -p "$scratch/$(dirname "$1")"; cp -L "$1" "$scratch/$1"; shift; done
shift
cd "$scratch"
"$tool" "$@" -o "$out"
"""

def _ahdpack_lightmap_impl(ctx):
    out = ctx.actions.declare_directory(ctx.label.name)
    inputs = [ctx.file.src] + ctx.files.srcs + ctx.files.formats
    args = ctx.actions.args()
    args.add(ctx.executable.ahdpack.path)
    args.add(out.path + "/" + ctx.label.name + "." + ctx.attr.container)
    args.add_all(inputs)
    args.add("--")
    args.add("convert")
    args.add(ctx.file.src)
    args.add("--profile", ctx.attr.profile)
    args.add_all(ctx.attr.options)
    args.add("-q")
    ctx.actions.run_shell(
        command = _RUN,
        arguments = [args],
        # The modules (libahd_*.so: Assimp for meshes, OpenImageIO for other image formats,
        # OpenColorIO for colour spaces) are opened beside the executable: tools of the action too.
        tools = [ctx.executable.ahdpack] + ctx.files.modules,
        # Every file the conversion reads must be here (`ahdpack convert --depfile` lists them): in
        # the sandbox an undeclared file is absent, and an absent .exr.import or L1 file changes
        # what the input is rather than failing.
        inputs = depset(inputs),
        outputs = [out],
        env = {"AHD_FORMATS_DIR": _formats_dir(ctx.files.formats)},
        mnemonic = "AhdpackLightmap",
        progress_message = "ahdpack %s" % ctx.label,
    )
    return [DefaultInfo(files = depset([out]))]

ahdpack_lightmap = rule(
    implementation = _ahdpack_lightmap_impl,
    doc = "Converts one SH lightmap (or a baker's set) to AHD planes with `ahdpack convert`.",
    attrs = {
        "src": attr.label(allow_single_file = True, mandatory = True, doc = "The input `ahdpack convert` is given"),
        "srcs": attr.label_list(
            allow_files = True,
            doc = "Every other file it reads: the baker's set (L1 images, .exr.import, .lmbake, " +
                  "project.godot, scene and meshes), normal maps, a profile .json",
        ),
        "profile": attr.string(default = "pc-bc"),
        "container": attr.string(default = "ktx2", values = ["ktx2", "dds"]),
        "options": attr.string_list(doc = "More `convert` options (paths in them must be declared in srcs)"),
        "ahdpack": attr.label(
            default = "//tools:ahdpack",
            executable = True,
            cfg = "exec",
            allow_files = True,
            doc = "The ahdpack executable (its bytes are part of every action's key)",
        ),
        "modules": attr.label(
            default = "//tools:ahdpack_modules",
            allow_files = True,
            cfg = "exec",
            doc = "ahdpack's modules (libahd_assimp.so, libahd_oiio.so, libahd_ocio.so), beside the " +
                  "executable: a filegroup of them (part of every action's key, as the executable)",
        ),
        "formats": attr.label(
            default = "//tools:ahdpack_formats",
            allow_files = True,
            doc = "ahdpack's formats/ folder (profiles, layout presets): a filegroup of its files",
        ),
    },
)
