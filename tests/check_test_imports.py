"""Every Python module the tests and scripts import comes from a package the project installs.

Reads every .py file under tests/ and scripts/, collects the modules it imports (anywhere in the
file, not only at the top), and the Python that the C++ tests run inline (`import x` inside their
string literals), and checks each one that is neither in Python's standard library nor
one of the project's own files: it must be importable by this interpreter (Debian's
/usr/bin/python3), its files must belong to a Debian package (dpkg -S), and that package must be
listed in scripts/install-deps.sh (its `packages` array). A module that pip, a recommended package or a hand install
provided on a developer machine would pass there and fail on a fresh one: this check fails first.

Usage: /usr/bin/python3 tests/check_test_imports.py [SOURCE_DIR]
Exit status 0 when every import is provided, 1 otherwise (one line per problem).
"""
import ast
import importlib.util
import os
import re
import subprocess
import sys

SOURCE_DIR = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else
                             os.path.join(os.path.dirname(__file__), ".."))
PACKAGE_LIST = os.path.join(SOURCE_DIR, "scripts", "install-deps.sh")


def listed_packages():
    """The packages of the `packages=( ... )` array of scripts/install-deps.sh."""
    packages = set()
    inside = False
    with open(PACKAGE_LIST) as f:
        for line in f:
            text = line.split("#", 1)[0].strip()
            if not inside:
                inside = text == "packages=("
                continue
            if text == ")":
                break
            packages.update(text.split())
    return packages


def python_files():
    for top in ("tests", "scripts"):
        for root, _, files in os.walk(os.path.join(SOURCE_DIR, top)):
            for name in sorted(files):
                if name.endswith(".py"):
                    yield os.path.join(root, name)


def imported_modules(path):
    """Top-level names of the absolute imports of one file."""
    with open(path) as f:
        tree = ast.parse(f.read(), filename=path)
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names.update(alias.name.split(".")[0] for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            names.add(node.module.split(".")[0])
    return names


# Python embedded in the C++ tests, e.g. run("/usr/bin/python3 -c 'import sep, astropy'").
EMBEDDED_IMPORT = re.compile(r"(?:^|[\s\"'(;])import\s+([A-Za-z_]\w*(?:\s*,\s*[A-Za-z_]\w*)*)")
EMBEDDED_FROM = re.compile(r"(?:^|[\s\"'(;])from\s+([A-Za-z_]\w*)[\w.]*\s+import\b")


def embedded_python_files():
    for root, _, files in os.walk(os.path.join(SOURCE_DIR, "tests")):
        for name in sorted(files):
            if name.endswith((".cpp", ".h")):
                yield os.path.join(root, name)


def embedded_imports(path):
    with open(path) as f:
        text = f.read()
    names = set(EMBEDDED_FROM.findall(text))
    # "from x import A, B" names x only: drop those statements before looking for "import y".
    text = re.sub(r"\bfrom\s+[\w.]+\s+import\s+\w+(?:\s*,\s*\w+)*", " ", text)
    for group in EMBEDDED_IMPORT.findall(text):
        names.update(n.strip().split(".")[0] for n in group.split(","))
    return names


def own_modules():
    """Modules the project itself provides: any .py file of tests/ or scripts/, and the
    packages of python/ (the octarc module, built with octarc)."""
    own = {os.path.splitext(os.path.basename(p))[0] for p in python_files()}
    packages = os.path.join(SOURCE_DIR, "python")
    if os.path.isdir(packages):
        own.update(name for name in os.listdir(packages)
                   if os.path.isfile(os.path.join(packages, name, "__init__.py")))
    return own


def owning_package(path):
    proc = subprocess.run(["dpkg", "-S", path], capture_output=True, text=True)
    if proc.returncode != 0:
        return None
    # "python3-numpy:amd64: /usr/lib/python3/dist-packages/numpy" (first match is enough)
    return proc.stdout.splitlines()[0].split(":")[0].strip()


def main():
    if not sys.executable.startswith("/usr/bin/"):
        print("check_test_imports: run me with Debian's /usr/bin/python3 (this is %s)" %
              sys.executable)
        return 1
    listed = listed_packages()
    own = own_modules()
    problems = []
    users = {}
    for path in python_files():
        for module in imported_modules(path):
            users.setdefault(module, []).append(os.path.relpath(path, SOURCE_DIR))
    for path in embedded_python_files():
        for module in embedded_imports(path):
            users.setdefault(module, []).append(os.path.relpath(path, SOURCE_DIR))
    for module in sorted(users):
        if module in sys.stdlib_module_names or module in own or module == "__future__":
            continue
        where = ", ".join(sorted(users[module]))
        spec = importlib.util.find_spec(module)
        if spec is None:
            problems.append("%s (imported by %s) is not installed: add the Debian package that "
                            "provides it to scripts/install-deps.sh" % (module, where))
            continue
        location = spec.origin if spec.origin not in (None, "namespace") else \
            next(iter(spec.submodule_search_locations or []), None)
        package = owning_package(location) if location else None
        if package is None:
            problems.append("%s (imported by %s) comes from %s, which no Debian package "
                            "provides" % (module, where, location))
        elif package not in listed:
            problems.append("%s (imported by %s) comes from the Debian package %s, which "
                            "scripts/install-deps.sh does not list" % (module, where, package))
    for p in problems:
        print("check_test_imports: " + p)
    if not problems:
        print("check_test_imports: every imported module comes from a listed package (%d "
              "third-party modules)" % sum(1 for m in users if m not in sys.stdlib_module_names
                                           and m not in own))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
