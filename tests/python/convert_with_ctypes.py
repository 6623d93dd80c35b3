"""The C API from Python through ctypes (standard library only), as a cook script would use it.

Loads the build's shared libahd and libahd_sample, bakes the built-in sample (ahd_sample_bake),
converts it (ahd_convert), writes the result's files, and compares every file but the report (its
seconds differ) byte for byte with what `ahdpack convert` writes for the same sample and options.
The cases set every field of ahd_options away from its default at least once, so a struct declared
out of the header's order gives other bytes, not a silent pass.

Usage: convert_with_ctypes.py LIBAHD_SO LIBAHD_SAMPLE_SO AHDPACK_EXE
Exit 0 when every file is identical, 1 on a difference or an error, 77 (ctest SKIP_RETURN_CODE)
when a shared library cannot be loaded.
"""
import ctypes
import os
import subprocess
import sys
import tempfile
import time

SKIP = 77


class ShInput(ctypes.Structure):
    """ahd_sh_input of <ahd/ahd.h>, field by field in the header's order."""
    _fields_ = [("width", ctypes.c_int), ("height", ctypes.c_int), ("coeffs", ctypes.c_int),
                ("sh", ctypes.POINTER(ctypes.c_float)), ("coverage", ctypes.POINTER(ctypes.c_ubyte)),
                ("normals", ctypes.POINTER(ctypes.c_float))]


class Options(ctypes.Structure):
    """ahd_options of <ahd/ahd.h>, field by field in the header's order (test
    OptionTable.CtypesMirrorHasEveryCMemberInOrder compares it with the option table)."""
    _fields_ = [("struct_size", ctypes.c_size_t), ("profile", ctypes.c_char_p), ("profile_json", ctypes.c_char_p), ("ratio", ctypes.c_int),
                ("direction_fit", ctypes.c_int), ("bc6h_quality", ctypes.c_int), ("threads", ctypes.c_int),
                ("eps", ctypes.c_double), ("closed_loop", ctypes.c_int), ("levels", ctypes.c_int),
                ("coverage_plane", ctypes.c_int), ("direction", ctypes.c_int),
                ("ambient_threshold", ctypes.c_double), ("container", ctypes.c_int), ("zstd", ctypes.c_int),
                ("plane_metadata", ctypes.c_int), ("measure", ctypes.c_int),
                ("iz_scale", ctypes.c_double), ("stable_names", ctypes.c_int)]


# (sample size, order, seed), the ahd_options fields set, the same conversion as `ahdpack convert` flags.
CASES = [
    ((256, 2, 0), {"profile": b"uncompressed"}, ["--profile", "uncompressed"], "ktx2"),
    ((256, 2, 0), {"profile": b"pc-bc"}, ["--profile", "pc-bc"], "ktx2"),
    ((96, 1, 3),
     {"profile": b"uncompressed-rgb", "ratio": 1, "direction_fit": 0, "threads": 1, "eps": 0.1, "closed_loop": 0,
      "levels": 3, "coverage_plane": 1, "direction": 1, "container": 1},
     ["--sample-size", "96", "--sample-order", "1", "--seed", "3", "--profile", "uncompressed-rgb", "--ratio", "rgb",
      "--direction-fit", "linear", "--threads", "1", "--eps", "0.1", "--open-loop", "--levels", "3",
      "--coverage-plane", "--direction", "keep"], "dds"),
    ((64, 2, 0),
     {"profile": b"pc-bc", "bc6h_quality": 0, "threads": 2, "ambient_threshold": 0.5, "zstd": 1, "plane_metadata": 0,
      "measure": 1},
     ["--sample-size", "64", "--profile", "pc-bc", "--quality", "fast", "--threads", "2", "--ambient-threshold", "0.5",
      "--zstd", "--strict-ktx"], "ktx2"),
]


def load(libahd_path, libsample_path):
    """The two shared libraries with the prototypes of the functions used (ctypes needs them for
    pointers and size_t; without them it passes int)."""
    ahd = ctypes.CDLL(libahd_path)
    sample = ctypes.CDLL(libsample_path)
    ahd.ahd_version.restype = ctypes.c_char_p
    ahd.ahd_options_init_size.argtypes = [ctypes.POINTER(Options), ctypes.c_size_t]
    ahd.ahd_convert.argtypes = [ctypes.POINTER(ShInput), ctypes.c_char_p, ctypes.POINTER(Options),
                                ctypes.POINTER(ctypes.c_void_p), ctypes.c_char_p, ctypes.c_size_t]
    ahd.ahd_result_file_count.argtypes = [ctypes.c_void_p]
    ahd.ahd_result_file_count.restype = ctypes.c_size_t
    ahd.ahd_result_file_name.argtypes = [ctypes.c_void_p, ctypes.c_size_t]
    ahd.ahd_result_file_name.restype = ctypes.c_char_p
    ahd.ahd_result_file_data.argtypes = [ctypes.c_void_p, ctypes.c_size_t, ctypes.POINTER(ctypes.c_size_t)]
    ahd.ahd_result_file_data.restype = ctypes.POINTER(ctypes.c_ubyte)
    ahd.ahd_result_free.argtypes = [ctypes.c_void_p]
    sample.ahd_sample_bake.argtypes = [ctypes.c_int, ctypes.c_int, ctypes.c_uint,
                                       ctypes.POINTER(ctypes.POINTER(ctypes.c_float)),
                                       ctypes.POINTER(ctypes.POINTER(ctypes.c_ubyte))]
    sample.ahd_sample_free.argtypes = [ctypes.c_void_p]
    return ahd, sample


def convert(ahd, sample, bake, fields, out_dir):
    """Bakes and converts through the C API into out_dir; returns the names of the files written."""
    size, order, seed = bake
    sh, cov = ctypes.POINTER(ctypes.c_float)(), ctypes.POINTER(ctypes.c_ubyte)()
    if sample.ahd_sample_bake(size, order, seed, ctypes.byref(sh), ctypes.byref(cov)) != 0:
        raise RuntimeError("ahd_sample_bake(%d, %d, %d) failed" % bake)
    inp = ShInput(size, size, 4 if order == 1 else 9, sh, cov, None)
    opt = Options()
    ahd.ahd_options_init_size(ctypes.byref(opt), ctypes.sizeof(opt))
    for k, v in fields.items():
        setattr(opt, k, v)
    result = ctypes.c_void_p()
    error = ctypes.create_string_buffer(512)
    rc = ahd.ahd_convert(ctypes.byref(inp), b"sample", ctypes.byref(opt), ctypes.byref(result), error, len(error))
    try:
        if rc != 0:
            raise RuntimeError("ahd_convert: " + error.value.decode())
        # A bad option is an error line and no result, not a crash.
        opt.direction = 7
        bad = ctypes.c_void_p()
        if ahd.ahd_convert(ctypes.byref(inp), b"x", ctypes.byref(opt), ctypes.byref(bad), error, len(error)) == 0 \
                or bad.value or b"direction" not in error.value:
            raise RuntimeError("ahd_convert accepted direction = 7")
        # A struct_size no version of ahd_options has (here 0, memory not from ahd_options_init) is refused.
        opt.direction = 0
        opt.struct_size = 0
        if ahd.ahd_convert(ctypes.byref(inp), b"x", ctypes.byref(opt), ctypes.byref(bad), error, len(error)) == 0 \
                or bad.value or b"struct_size" not in error.value:
            raise RuntimeError("ahd_convert accepted struct_size = 0")
    finally:
        sample.ahd_sample_free(ctypes.cast(sh, ctypes.c_void_p))
        sample.ahd_sample_free(ctypes.cast(cov, ctypes.c_void_p))
    names = []
    for i in range(ahd.ahd_result_file_count(result)):
        size_out = ctypes.c_size_t()
        data = ahd.ahd_result_file_data(result, i, ctypes.byref(size_out))
        name = ahd.ahd_result_file_name(result, i).decode()
        with open(os.path.join(out_dir, name), "wb") as f:
            f.write(ctypes.string_at(data, size_out.value))
        names.append(name)
    if ahd.ahd_result_file_name(result, len(names)) is not None:
        raise RuntimeError("ahd_result_file_name is not NULL past the last file")
    ahd.ahd_result_free(result)
    return names


def compare(label, cli_dir, py_dir, py_names):
    """Number of files compared equal, or an exception naming the first difference."""
    cli_names = sorted(n for n in os.listdir(cli_dir) if not n.endswith(".report.json"))
    if cli_names != sorted(n for n in py_names if not n.endswith(".report.json")):
        raise RuntimeError("%s: the CLI wrote %s, the C API %s" % (label, cli_names, sorted(py_names)))
    for name in cli_names:
        with open(os.path.join(cli_dir, name), "rb") as a, open(os.path.join(py_dir, name), "rb") as b:
            if a.read() != b.read():
                raise RuntimeError("%s: %s differs between the CLI and the C API" % (label, name))
    return len(cli_names)


def main():
    if len(sys.argv) != 4:
        print(__doc__)
        return 1
    libahd, libsample, cli = sys.argv[1:]
    try:
        ahd, sample = load(libahd, libsample)
    except OSError as e:  # e.g. an instrumented (ASan) library in an uninstrumented python
        print("skipped: cannot load the shared libraries: %s" % e)
        return SKIP
    print("libahd %s (%s)" % (ahd.ahd_version().decode(), libahd))
    with tempfile.TemporaryDirectory() as tmp:
        for i, (bake, fields, flags, ext) in enumerate(CASES):
            label = "case %d (%s)" % (i, " ".join(flags))
            py_dir, cli_dir = os.path.join(tmp, str(i), "py"), os.path.join(tmp, str(i), "cli")
            os.makedirs(py_dir)
            os.makedirs(cli_dir)
            t0 = time.monotonic()
            try:
                names = convert(ahd, sample, bake, fields, py_dir)
                subprocess.run([cli, "convert", "-q", "-o", os.path.join(cli_dir, "sample." + ext)] + flags, check=True)
                n = compare(label, cli_dir, py_dir, names)
            except (RuntimeError, subprocess.CalledProcessError) as e:
                print("FAIL: %s: %s" % (label, e))
                return 1
            if n < 4:
                print("FAIL: %s: only %d files compared" % (label, n))
                return 1
            print("%s: %d files identical (Python ctypes, CLI), %.1f s" % (label, n, time.monotonic() - t0))
    return 0


if __name__ == "__main__":
    sys.exit(main())
