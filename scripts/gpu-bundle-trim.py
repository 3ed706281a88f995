#!/usr/bin/env python3
"""Trims a bundle made by scripts/gpu-bundle.sh so that it fits the device tool's 64 MiB limit.

OpenCV, as Debian builds it, links every optional codec and video back end (GDAL, GDCM,
FFmpeg, GStreamer, libdc1394, libgphoto2): about 250 MB of libraries that reading PNG/JPEG files,
`ellipsekit conform` and `ellipsekit_bench` never call, but that the dynamic loader must find.
Each such library (STUB_ROOTS) is replaced by a generated stub: same soname, the same symbol
versions, and exactly the symbols the kept objects import from it; each function writes
"<library> is a stub ... <symbol> was called" to stderr and aborts (but those in NO_OPS return),
each data object is zeros.
Then every library no kept object needs any more is deleted.

usage: gpu-bundle-trim.py BUNDLE_DIR       (needs readelf and a C compiler: cc)
"""
import fnmatch
import os
import re
import subprocess
import sys
import tempfile

STUB_ROOTS = ["libgdal.so.*", "libgdcm*.so.*", "libdc1394.so.*", "libgst*.so.*",
              "libglib-2.0.so.*", "libgobject-2.0.so.*", "libavcodec.so.*", "libavformat.so.*",
              "libavutil.so.*", "libswscale.so.*", "libswresample.so.*", "libgphoto2*.so.*"]
# Functions OpenCV calls whether or not the library is used, made to return instead of abort
# (void functions only). GDALAllRegister: imgcodecs' GdalDecoder constructor, on the first imread.
NO_OPS = {"GDALAllRegister"}


def readelf(*args):
    return subprocess.run(["readelf", "-W", *args], check=True, capture_output=True, text=True).stdout


def needed(path):
    return re.findall(r"\(NEEDED\)\s+Shared library: \[([^\]]+)\]", readelf("-d", path))


def dyn_syms(path):
    """(name, version or None, default?, type, size, defined?) for each dynamic symbol."""
    out = []
    for line in readelf("--dyn-syms", path).splitlines():
        f = line.split()
        if len(f) < 8 or not f[0].endswith(":") or not f[0][:-1].isdigit():
            continue
        value, size, typ, bind, ndx, name = f[1], f[2], f[3], f[4], f[6], f[7]
        if not name or bind == "LOCAL" or typ in ("SECTION", "FILE"):
            continue
        version, default = None, True
        if "@@" in name:
            name, version = name.split("@@", 1)
        elif "@" in name:
            name, version = name.split("@", 1)
            default = False
        size = int(size, 16) if size.startswith("0x") else int(size)
        out.append((name, version, default, typ, size, ndx != "UND"))
    return out


def c_string(s):
    return '"' + s.replace("\\", "\\\\").replace('"', '\\"') + '"'


def make_stub(real, soname, wanted, workdir, dest):
    """Writes dest: a stub of `real` defining the symbols in `wanted` (names) that `real` defines."""
    defs = {}
    for name, version, default, typ, size, defined in dyn_syms(real):
        if not defined or name not in wanted:
            continue
        if name in defs and not default:  # keep the default version where there are several
            continue
        defs[name] = (version, typ, size)
    lines = ["#include <stdlib.h>", "#include <string.h>", "#include <unistd.h>",
             "static void stub_called(const char* sym) {",
             "  static const char a[] = \"ellipsekit GPU bundle: %s is a stub (scripts/gpu-bundle-trim.py); \";" % soname,
             "  (void)!write(2, a, sizeof a - 1); (void)!write(2, sym, strlen(sym));",
             "  (void)!write(2, \" was called\\n\", 12); abort();", "}"]
    versions = {}
    for i, (name, (version, typ, size)) in enumerate(sorted(defs.items())):
        label = c_string(name)
        if typ in ("FUNC", "IFUNC", "NOTYPE"):
            lines.append("void s%d(void) __asm__(%s);" % (i, label))
            lines.append("void s%d(void) { %s }" % (i, "" if name in NO_OPS else "stub_called(%s);" % label))
        elif typ == "OBJECT":
            lines.append("__attribute__((aligned(64))) char s%d[%d] __asm__(%s) = {0};" % (i, max(size, 1), label))
        elif typ == "TLS":
            lines.append("__thread char s%d[%d] __asm__(%s) = {0};" % (i, max(size, 1), label))
        else:
            raise SystemExit("gpu-bundle-trim.py: %s: symbol %s of type %s" % (real, name, typ))
        versions.setdefault(version, []).append(name)
    src = os.path.join(workdir, soname + ".c")
    with open(src, "w") as f:
        f.write("\n".join(lines) + "\n")
    cmd = ["cc", "-shared", "-fPIC", "-O1", "-w", "-o", dest, src, "-Wl,-soname," + soname]
    named = [v for v in versions if v]
    if named:
        script = os.path.join(workdir, soname + ".map")
        with open(script, "w") as f:
            # Every version the real library defines, in its order, so that any version an
            # importer requires (not only those of the imported symbols) is there.
            order = re.findall(r"Name: (\S+)", readelf("-V", real).split("Version needs section")[0])
            order = [v for v in order if v != soname and v != os.path.basename(real)]
            for v in dict.fromkeys(order + named):
                syms = versions.get(v, []) + (versions.get(None, []) if v == named[0] else [])
                f.write("%s {\n%s};\n" % (v, ("  global:\n" + "".join("    %s;\n" % s for s in syms)) if syms else ""))
        cmd.append("-Wl,--version-script=" + script)
    subprocess.run(cmd, check=True)
    return len(defs)


def main():
    if len(sys.argv) != 2:
        raise SystemExit(__doc__)
    bundle = os.path.abspath(sys.argv[1])
    lib, compat = os.path.join(bundle, "lib"), os.path.join(bundle, "lib", "compat")
    libs = {}  # soname -> path in the bundle
    for d in (lib, compat):
        for n in os.listdir(d):
            if ".so" in n and os.path.isfile(os.path.join(d, n)):
                libs[n] = os.path.join(d, n)
    bins = [os.path.join(bundle, "bin", n) for n in os.listdir(os.path.join(bundle, "bin"))]
    stubbed = {n for n in libs if any(fnmatch.fnmatch(n, p) for p in STUB_ROOTS)}

    # What the programs still reach when the stubbed libraries need nothing.
    kept, todo = set(), list(bins)
    while todo:
        obj = todo.pop()
        for n in needed(obj):
            if n in libs and n not in kept:
                kept.add(n)
                if n not in stubbed:
                    todo.append(libs[n])
    importers = bins + [libs[n] for n in kept if n not in stubbed]
    wanted = set()
    for obj in importers:
        wanted.update(name for name, _, _, _, _, defined in dyn_syms(obj) if not defined)

    with tempfile.TemporaryDirectory() as work:
        for n in sorted(stubbed & kept):
            tmp = os.path.join(work, n)
            count = make_stub(libs[n], n, wanted, work, tmp)
            os.replace(tmp, libs[n])
            print("gpu-bundle-trim.py: %s -> stub of %d symbols" % (n, count))
    removed = sorted(set(libs) - kept)
    for n in removed:
        os.remove(libs[n])
    print("gpu-bundle-trim.py: %d libraries kept (%d of them stubs), %d removed as unreachable"
          % (len(kept), len(stubbed & kept), len(removed)))


if __name__ == "__main__":
    main()
