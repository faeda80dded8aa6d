"""octarc installed: `cmake --install` into a temporary prefix, a copy of that tree run with
nothing of the source or build tree in sight (every file octarc opens is recorded with strace);
and the Debian package `cpack -G DEB` makes, with its contents and runtime dependencies."""
import filecmp
import glob
import os
import re
import shutil
import subprocess
import sys
import unittest

import numpy as np
from astropy.io import fits

from octarc_testlib import OCTARC, SOURCE_DIR, WorkDirTest, param_names, require_program

BUILD_DIR = os.environ.get("OCTARC_BUILD_DIR", "")
CMAKE = os.environ.get("OCTARC_CMAKE", "cmake")
CPACK = os.environ.get("OCTARC_CPACK", "cpack")

# Every installed file and, for the data, its source in the tree.
DATA = {"octarc.sex": "params/octarc.sex", "octarc.param": "params/octarc.param",
        "default.conv": "params/default.conv", "demo.grid.fits": "params/demo.grid.fits",
        "dls.grid.fits": "params/dls.grid.fits", "demo.model.fits": "params/demo.model.fits",
        "simulation/population.txt": "params/simulation/population.txt",
        "simulation/population-dls.txt": "params/simulation/population-dls.txt"}
LIBRARIES = ["core", "cluster", "io", "plot", "background", "detection", "measure", "catalog",
             "selection", "sexcompat", "run", "simulation", "simulation_engine", "lenslight",
             "calibration", "search", "batch", "app"]


def tree_files(folder):
    """The files under a folder of the source tree, relative to it."""
    root = os.path.join(SOURCE_DIR, folder)
    return [os.path.relpath(os.path.join(d, f), root) for d, _, names in os.walk(root)
            for f in names]


# The man pages: octarc(1) and one per command.
COMMANDS = ["measure", "detect", "simulate lenses", "simulate field", "simulate database",
            "calibrate", "search", "batch", "grades", "inject", "demo"]
MAN_PAGES = ["octarc.1"] + ["octarc-%s.1" % c.replace(" ", "-") for c in COMMANDS]

# Every installed file: the program and its data, the documentation (README, LICENSE, docs/,
# the man pages), and the libraries with their headers and CMake package.
INSTALLED = sorted(
    ["bin/octarc", "share/doc/octarc/README.md", "share/doc/octarc/LICENSE"] +
    ["share/man/man1/" + name for name in MAN_PAGES] +
    ["share/doc/octarc/" + name for name in tree_files("docs")] +
    ["share/octarc/" + name for name in DATA] +
    ["lib/liboctarc_%s.a" % name for name in LIBRARIES] +
    ["include/" + name for name in tree_files("include")] +
    ["include/" + name for name in tree_files("sextractor_compat/include")] +
    ["lib/cmake/octarc/" + name for name in ("octarcConfig.cmake", "octarcConfigVersion.cmake",
                                             "octarcTargets.cmake", "octarcTargets-BUILDTYPE.cmake")])


# The Python module, when the build tree has it (OCTARC_PYTHON_MODULE names its file): the octarc
# package in Python's site directory under the prefix, lib/python3/dist-packages for /usr (the
# Debian package), lib/python3.X/site-packages for another prefix (python/CMakeLists.txt).
PYTHON_MODULE = os.environ.get("OCTARC_PYTHON_MODULE", "")
PREFIX_SITE = "lib/python%d.%d/site-packages" % sys.version_info[:2]


def python_package(site):
    if not PYTHON_MODULE:
        return []
    names = ("__init__.py", "__main__.py", "_search.py", "_selection.py", PYTHON_MODULE)
    return ["%s/octarc/%s" % (site, name) for name in names]


INSTALLED_IN_PREFIX = sorted(INSTALLED + python_package(PREFIX_SITE))
INSTALLED_BY_PACKAGE = sorted(INSTALLED + python_package("lib/python3/dist-packages"))


def files_under(root):
    """The files under root, relative to it; the CMake targets file of the build type
    (octarcTargets-release.cmake...) named octarcTargets-BUILDTYPE.cmake."""
    return sorted(re.sub(r"octarcTargets-[a-z]+\.cmake$", "octarcTargets-BUILDTYPE.cmake",
                         os.path.relpath(os.path.join(d, f), root))
                  for d, _, names in os.walk(root) for f in names)


def run_version(octarc):
    """The version an octarc executable prints (`octarc -v`)."""
    return subprocess.run([octarc, "-v"], capture_output=True, text=True).stdout.split()[-1]


def has_debug_info(binary):
    sections = subprocess.run(["readelf", "-S", binary], capture_output=True, text=True).stdout
    return ".debug_info" in sections


@unittest.skipUnless(BUILD_DIR, "OCTARC_BUILD_DIR (the build tree) is set by ctest")
class InstalledTree(WorkDirTest):

    def run_traced(self, tag, args, cwd, env):
        """Runs the octarc found on env's PATH under strace; returns (process, paths opened)."""
        trace = self.path("trace.%s.txt" % tag)
        # LeakSanitizer cannot run under ptrace: a sanitizer build checks leaks in other tests.
        env = dict(env, ASAN_OPTIONS=":".join(filter(None, [env.get("ASAN_OPTIONS"),
                                                              "detect_leaks=0"])))
        proc = subprocess.run(["strace", "-f", "-qq", "-e", "trace=%file", "-o", trace, "octarc"] +
                              args, cwd=cwd, env=env, capture_output=True, text=True)
        self.assertEqual(proc.returncode, 0, proc.stderr)
        with open(trace) as f:
            paths = re.findall(r'"([^"]*)"', f.read())
        return proc, paths

    def test_a_copy_of_the_installed_tree_runs_demo_and_detect(self):
        prefix = self.path("prefix")
        subprocess.run([CMAKE, "--install", BUILD_DIR, "--prefix", prefix], check=True,
                       capture_output=True)
        self.assertEqual(files_under(prefix), INSTALLED_IN_PREFIX)
        for name, source in DATA.items():
            self.assertTrue(filecmp.cmp(os.path.join(prefix, "share", "octarc", name),
                                        os.path.join(SOURCE_DIR, source), shallow=False), name)
        # Only the copy exists: the installed tree is gone, and neither the source nor the
        # build tree is on the PATH, the working directory or the environment.
        moved = self.path("moved")
        shutil.copytree(prefix, moved, symlinks=True)
        shutil.rmtree(prefix)
        work = self.path("work")
        os.mkdir(work)
        env = {"PATH": os.path.join(moved, "bin") + ":/usr/bin:/bin", "HOME": work, "LC_ALL": "C"}
        for key in ("ASAN_OPTIONS", "UBSAN_OPTIONS"):
            if key in os.environ:
                env[key] = os.environ[key]
        trees = [os.path.realpath(SOURCE_DIR), os.path.realpath(BUILD_DIR)]
        for tree in trees:
            self.assertFalse(any(tree in value for value in env.values()), tree)
            self.assertFalse(os.path.realpath(work).startswith(tree))
        if not has_debug_info(os.path.join(moved, "bin", "octarc")):
            # No path of the build compiled in (a build with debug information names its
            # sources, which the traces below still show are never opened).
            with open(os.path.join(moved, "bin", "octarc"), "rb") as f:
                binary = f.read()
            for tree in trees:
                self.assertNotIn(tree.encode(), binary)

        # The demo: its field simulated, searched with the shipped octarc.sex, octarc.param and
        # demo lens model.
        shipped = os.path.join(moved, "share", "octarc")
        proc, opened = self.run_traced("demo", ["demo", "--size", "512", "--lenses", "3",
                                                "--seed", "2", "--out", "demo", "--quiet"],
                                       work, env)
        self.assertIn("Detection: octarc search -c %s/octarc.sex (15 levels" % shipped,
                      proc.stdout)
        self.assertIn("Search: octarc search -SELECTION_METHOD TREES -MODEL_NAME "
                      "%s/demo.model.fits" % shipped, proc.stdout)
        self.assertIn("Injected arcs detected:", proc.stdout)
        # The field's lenses follow the Deep Lens Survey preset.
        for name in ("octarc.sex", "octarc.param", "demo.model.fits",
                     "simulation/population-dls.txt"):
            self.assertIn(os.path.join(shipped, name), opened)
        rows = fits.getdata(os.path.join(work, "demo", "field.ldac"), "LDAC_OBJECTS")
        self.assertEqual(sorted(set(rows["THRESH_LEVEL"])), list(range(1, 16)))
        demo_opened = opened

        # detect -c <copy>/share/octarc/octarc.sex on the demo's field, from the work directory:
        # its PARAMETERS_NAME (octarc.param) and CATALOG_NAME (octarc.ldac) as the file says.
        proc, opened = self.run_traced("detect", ["detect", "demo/field.fits", "-c",
                                                  os.path.join(shipped, "octarc.sex")], work, env)
        self.assertNotIn("WARNING", proc.stderr)
        self.assertIn(os.path.join(shipped, "octarc.param"), opened)
        catalog = os.path.join(work, "octarc.ldac")
        with fits.open(catalog) as f:
            rows = f["LDAC_OBJECTS"].data
            imhead = fits.Header.fromstring("".join(c.ljust(80) for c in f[1].data[0][0]))
        self.assertEqual(rows.columns.names, param_names(os.path.join(shipped, "octarc.param")))
        self.assertEqual(sorted(set(rows["THRESH_LEVEL"])), list(range(1, 16)))
        # octarc.sex: 15 levels log-spaced from 2.5 to 20 sigma.
        self.assertEqual(imhead["OCTNLEV"], 15)
        sigma = imhead["SEXBKDEV"]
        thresholds = np.array([imhead["OCTTH%d" % n] for n in range(1, 16)])
        np.testing.assert_allclose(thresholds, 2.5 * sigma * 8.0 ** (np.arange(15) / 14.0),
                                   rtol=1e-9)

        if PYTHON_MODULE:
            # The copy's Python module imports and detects, from its own site directory.
            proc = subprocess.run(
                ["/usr/bin/python3", "-c",
                 "import numpy as np, octarc; print(octarc.__version__, "
                 "octarc._shipped_data_directory(), "
                 "octarc.detect(np.ones((20, 20), 'f4'), 0.5, background=0.0, "
                 "error=1.0).objects_per_level)"],
                cwd=work, env=dict(env, PYTHONPATH=os.path.join(moved, PREFIX_SITE)),
                capture_output=True, text=True)
            self.assertEqual(proc.returncode, 0, proc.stderr)
            # Its data files are the copy's (share/octarc), not beside python3.
            self.assertEqual(proc.stdout.split(maxsplit=2),
                             [run_version(os.path.join(moved, "bin", "octarc")),
                              os.path.join(moved, "share", "octarc"), "[1]\n"])

        # Nothing of the source or build tree was even looked at.
        for path in demo_opened + opened:
            real = os.path.realpath(os.path.join(work, path))
            for tree in trees:
                self.assertFalse(path.startswith(tree) or real.startswith(tree), path)


    def test_man_pages_say_what_the_commands_print(self):
        # Each page holds its command's -h text and, for a command, every key of its -dd
        # listing; mandoc's linter finds no warning or error in any.
        require_program("mandoc")
        prefix = self.path("prefix")
        subprocess.run([CMAKE, "--install", BUILD_DIR, "--prefix", prefix], check=True,
                       capture_output=True)
        for command, name in zip([""] + COMMANDS, MAN_PAGES):
            page = os.path.join(prefix, "share", "man", "man1", name)
            lint = subprocess.run(["mandoc", "-T", "lint", "-W", "warning", page],
                                  capture_output=True, text=True)
            self.assertEqual(lint.returncode, 0, lint.stdout + lint.stderr)
            # The page as a reader sees it, as plain text.
            text = subprocess.run(["mandoc", "-T", "ascii", "-O", "width=200", page],
                                  check=True, capture_output=True, text=True).stdout
            text = re.sub(r".\x08", "", text)  # overstrike (bold) removed
            args = command.split()
            usage = subprocess.run([OCTARC, *args, "-h"], check=True, capture_output=True,
                                   text=True).stdout
            for line in usage.splitlines():
                self.assertIn(line.strip(), text, name)
            title = "octarc" + "".join("-" + a for a in args)
            self.assertIn("%s - " % title, text, name)
            if command:
                keys = subprocess.run([OCTARC, *args, "-dd"], check=True, capture_output=True,
                                      text=True).stdout
                # A key starts its line; a comment's continuation is indented.
                names = [line.split()[0] for line in keys.splitlines()
                         if line and line[0] not in " #"]
                self.assertGreater(len(names), 0, name)
                for key in names:
                    self.assertRegex(text, r"(^|\n) *%s( |\n)" % re.escape(key), (name, key))

    def test_a_program_of_ones_own_builds_against_the_installed_libraries(self):
        # find_package(octarc) in a project of its own: the installed headers and libraries,
        # and their dependencies found again by the package's config file (octarc::app, which
        # links every other target).
        prefix = self.path("prefix")
        subprocess.run([CMAKE, "--install", BUILD_DIR, "--prefix", prefix], check=True,
                       capture_output=True)
        project = self.path("project")
        os.mkdir(project)
        with open(os.path.join(project, "CMakeLists.txt"), "w") as f:
            f.write("cmake_minimum_required(VERSION 3.18)\n"
                    "project(pixelsum LANGUAGES CXX)\n"
                    "set(CMAKE_CXX_STANDARD 20)\n"
                    "find_package(octarc 0.1 REQUIRED)\n"
                    "add_executable(pixelsum main.cpp)\n"
                    "target_link_libraries(pixelsum PRIVATE octarc::app)\n")
        with open(os.path.join(project, "main.cpp"), "w") as f:
            f.write("#include <cstdio>\n"
                    "#include \"octarc/io/FitsImage.h\"\n"
                    "#include \"octarc/search/SearchKeys.h\"\n"
                    "int main(int argc, char** argv) {\n"
                    "  if (argc != 2) return 2;\n"
                    "  const octarc::ImageHdu hdu = octarc::readImage(argv[1]);\n"
                    "  double sum = 0.0;\n"
                    "  for (std::int64_t y = 0; y < hdu.pixels.height(); ++y)\n"
                    "    for (std::int64_t x = 0; x < hdu.pixels.width(); ++x)\n"
                    "      sum += hdu.pixels(x, y);\n"
                    "  std::printf(\"%lld %lld %.17g %zu\\n\", (long long)hdu.pixels.width(),\n"
                    "              (long long)hdu.pixels.height(), sum,\n"
                    "              octarc::searchKeys().size());\n"
                    "  return 0;\n"
                    "}\n")
        build = self.path("project-build")
        for cmd in ([CMAKE, "-S", project, "-B", build, "-G", "Ninja",
                     "-DCMAKE_PREFIX_PATH=" + prefix],
                    [CMAKE, "--build", build]):
            proc = subprocess.run(cmd, capture_output=True, text=True)
            self.assertEqual(proc.returncode, 0, proc.stdout + proc.stderr)
        image = os.path.join(SOURCE_DIR, "testdata", "example.fits.gz")
        out = subprocess.run([os.path.join(build, "pixelsum"), image], check=True,
                             capture_output=True, text=True).stdout.split()
        data = fits.getdata(image).astype(np.float64)
        self.assertEqual((int(out[0]), int(out[1])), (data.shape[1], data.shape[0]))
        self.assertAlmostEqual(float(out[2]), data.sum(), delta=1e-12 * np.abs(data).sum())
        # octarc::app holds every stage (and Ceres, XGBoost, PLplot, MPI behind them): the
        # search's key table, as long as `octarc search -dd` lists it.
        dump = subprocess.run([OCTARC, "search", "-dd"], check=True, capture_output=True,
                              text=True).stdout
        keys = [line for line in dump.splitlines() if line and line[0] not in " #"]
        self.assertEqual(int(out[3]), len(keys))

    def test_an_executable_without_its_data_says_where_it_looked(self):
        bindir = self.path("bin")
        os.mkdir(bindir)
        shutil.copy(OCTARC, bindir)
        env = {"PATH": bindir + ":/usr/bin:/bin", "LC_ALL": "C"}
        # LSAN_OPTIONS too: the demo's stamps reach fontconfig, whose caches tests/lsan.supp
        # names (the first test runs under strace, without leak checks).
        for key in ("ASAN_OPTIONS", "UBSAN_OPTIONS", "LSAN_OPTIONS"):
            if key in os.environ:
                env[key] = os.environ[key]
        expected = os.path.join(self.work, "share", "octarc", "octarc.sex")
        proc = subprocess.run(["octarc", "demo", "--size", "256", "--out", "demo"], cwd=self.work,
                              env=env, capture_output=True, text=True)
        self.assertNotEqual(proc.returncode, 0)
        lines = [line for line in proc.stderr.splitlines() if line.strip()]
        self.assertEqual(len(lines), 1, proc.stderr)
        self.assertIn(expected + ": octarc data file not found", lines[0])
        self.assertIn("OCTARC_DATA_DIR", lines[0])
        self.assertEqual(sorted(os.listdir(self.work)), ["bin"])
        # OCTARC_DATA_DIR names another place.
        data = os.path.join(SOURCE_DIR, "params")
        env["OCTARC_DATA_DIR"] = data
        proc = subprocess.run(["octarc", "demo", "--size", "256", "--lenses", "1", "--out", "demo",
                               "--quiet"], cwd=self.work, env=env, capture_output=True, text=True)
        self.assertEqual(proc.returncode, 0, proc.stderr)
        self.assertIn("octarc search -c %s/octarc.sex" % data, proc.stdout)
        self.assertTrue(os.path.exists(os.path.join(self.work, "demo", "field.ldac")))


@unittest.skipUnless(BUILD_DIR, "OCTARC_BUILD_DIR (the build tree) is set by ctest")
class DebianPackage(WorkDirTest):

    def package_of(self, library):
        """The Debian package that holds a shared library (dpkg -S), e.g. libcfitsio10."""
        candidates = [library, os.path.realpath(library)]
        if library.startswith("/lib/"):
            candidates.append("/usr" + library)
        for path in candidates:
            proc = subprocess.run(["dpkg", "-S", path], capture_output=True, text=True)
            if proc.returncode == 0:
                return proc.stdout.split(":")[0].strip()
        self.fail("no Debian package holds " + library)

    def configured_maintainer(self):
        """OCTARC_PACKAGE_MAINTAINER of the build tree ("" when not given)."""
        with open(os.path.join(BUILD_DIR, "CMakeCache.txt")) as f:
            found = re.search(r"^OCTARC_PACKAGE_MAINTAINER:STRING=(.*)$", f.read(), re.M)
        return found.group(1) if found else ""

    def cpack(self, out, **env):
        return subprocess.run([CPACK, "-G", "DEB", "--config",
                               os.path.join(BUILD_DIR, "CPackConfig.cmake"), "-B", out],
                              capture_output=True, text=True,
                              env={**os.environ, "DEBFULLNAME": "", "DEBEMAIL": "", **env})

    def test_package_holds_octarc_its_data_and_dependencies(self):
        # The maintainer, as Debian's tools take it, from DEBFULLNAME and DEBEMAIL (the build
        # tree of the tests is configured without OCTARC_PACKAGE_MAINTAINER).
        out = self.path("package")
        proc = self.cpack(out, DEBFULLNAME="Ada Lovelace", DEBEMAIL="ada@example.org")
        self.assertEqual(proc.returncode, 0, proc.stdout + proc.stderr)
        debs = glob.glob(os.path.join(out, "*.deb"))
        self.assertEqual(len(debs), 1, debs)
        listing = subprocess.run(["dpkg-deb", "-c", debs[0]], check=True, capture_output=True,
                                 text=True).stdout
        files = sorted(re.sub(r"octarcTargets-[a-z]+\.cmake$", "octarcTargets-BUILDTYPE.cmake",
                              line.split()[-1][len("./usr/"):])
                       for line in listing.splitlines() if not line.startswith("d"))
        self.assertEqual(files, INSTALLED_BY_PACKAGE)
        # The program is stripped: no symbol table, no debug information.
        unpacked = self.path("unpacked")
        subprocess.run(["dpkg-deb", "-x", debs[0], unpacked], check=True)
        sections = subprocess.run(["readelf", "-S", os.path.join(unpacked, "usr", "bin", "octarc")],
                                  capture_output=True, text=True, check=True).stdout
        self.assertNotIn(".symtab", sections)
        self.assertNotIn(".debug_info", sections)

        def field(name):
            return subprocess.run(["dpkg-deb", "-f", debs[0], name], check=True,
                                  capture_output=True, text=True).stdout.strip()

        self.assertEqual(field("Package"), "octarc")
        self.assertEqual(field("Maintainer"),
                         self.configured_maintainer() or "Ada Lovelace <ada@example.org>")
        version = subprocess.run([OCTARC, "detect", "-v"], capture_output=True,
                                 text=True).stdout.split()[-1]
        self.assertEqual(field("Version"), version)
        arch = subprocess.run(["dpkg", "--print-architecture"], capture_output=True,
                              text=True).stdout.strip()
        self.assertEqual(field("Architecture"), arch)
        # Depends: the package of every shared library octarc links.
        depends = {d.split()[0] for d in field("Depends").split(",")}
        needed = re.findall(r"\(NEEDED\)\s+Shared library: \[(.*)\]",
                            subprocess.run(["readelf", "-d", OCTARC], capture_output=True,
                                           text=True).stdout)
        libraries = subprocess.run(["ldd", OCTARC], capture_output=True, text=True).stdout
        resolved = dict(re.findall(r"^\s*(\S+) => (\S+)", libraries, re.M))
        # The dynamic loader, which ldd names by its path alone: NEEDED by an executable whose
        # libraries were compiled position-independent (for the Python module), as their
        # thread-local variables refer to its __tls_get_addr.
        resolved.update((os.path.basename(path), path)
                        for path in re.findall(r"^\s*(/\S+) \(", libraries, re.M))
        expected = {self.package_of(resolved[lib]) for lib in needed}
        self.assertTrue(expected <= depends, (expected, depends))
        for name in ("cfitsio", "wcs", "boost-program-options"):
            self.assertTrue(any(name in d for d in depends), (name, depends))


    def test_a_package_without_a_maintainer_address_is_refused(self):
        if self.configured_maintainer():
            self.skipTest("this build tree is configured with OCTARC_PACKAGE_MAINTAINER")
        out = self.path("package")
        for env in ({}, {"DEBFULLNAME": "Ada Lovelace", "DEBEMAIL": "not an address"}):
            proc = self.cpack(out, **env)
            self.assertNotEqual(proc.returncode, 0, env)
            self.assertIn("the Debian package needs a maintainer: set DEBFULLNAME and DEBEMAIL",
                          proc.stdout + proc.stderr)
            self.assertEqual(glob.glob(os.path.join(out, "*.deb")), [])


if __name__ == "__main__":
    unittest.main()
