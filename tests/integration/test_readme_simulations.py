"""Every command line of the README's Simulations and Calibration sections, run as printed.

The command lines are read from the README's ```sh blocks between "## Simulations" and
"## Search" (continued lines joined, comments dropped) and must be those this test knows: a
command added to those sections without being run here fails the test. Where the README prints
what a command gives (the colour cut of the small two-band run), the printed lines are compared
with the run's. The long studies' lines (the calibration of 150 000 systems) are those that
scripts/readme_studies.py runs and compares with the README, by hand. The synopsis lines of
`simulate database` and `simulate field` are run by test_build_database.py and
test_simulate_field.py.
"""
import os
import re
import shlex
import sys
import unittest

from octarc_testlib import SOURCE_DIR, WorkDirTest, run_octarc

sys.path.insert(0, os.path.join(SOURCE_DIR, "scripts"))
import readme_studies  # noqa: E402  (scripts/readme_studies.py)

README = os.path.join(SOURCE_DIR, "README.md")
IMAGE = os.path.join(SOURCE_DIR, "testdata", "example.fits.gz")


def sections():
    with open(README) as f:
        text = f.read()
    return text[text.index("\n## Simulations"):text.index("\n## Search")]


def readme_commands():
    """The `octarc ...` lines of the sections' sh blocks, read as scripts/readme_studies.py
    reads its own."""
    commands = []
    for block in re.findall(r"```sh\n(.*?)```", sections(), re.S):
        commands += readme_studies.octarc_lines(block)
    return commands


def printed_block_after(marker):
    """The lines of the first plain (language-less) ``` block after `marker` in the sections."""
    text = sections()
    lines = text[text.index(marker):].splitlines()
    inside, language, block = False, "", []
    for line in lines:
        if line.startswith("```"):
            if not inside:
                inside, language, block = True, line[3:].strip(), []
                continue
            inside = False
            if language == "":
                return block
            continue
        if inside:
            block.append(line)
    raise AssertionError("no printed block after " + marker)


# What the sections' command lines are, and what each needs first (files made by the test).
KNOWN = [
    "octarc simulate lenses -n 6000 --seed 9 --preset dls -o sim.fits",
    "octarc calibrate sim.fits",
    'octarc calibrate sim.fits -SEARCH_NAME strong -SEARCH_CUT "ARCNESS > 0.15 && E_IMAGE > 0.6" '
    "-SURVEY_CATALOG field.ldac -CHECKPLOT_DEV PDF -THRESHOLD_STUDY Y",
    "octarc calibrate -dd",
    "octarc simulate lenses -n 150000 --seed 31 --preset dls -o dls150k.fits",
    "octarc calibrate dls150k.fits",
    "octarc simulate lenses -n 30000 --seed 13 --preset dls -o sim-g.fits --band g "
    "--source-colour 0.4,0.3 --lens-colour 1.2,0.1",
    "octarc calibrate sim-g.fits -COLOUR_CUT_MAX -1,3,0.05",
]


class ReadmeSimulations(WorkDirTest):
    def run_line(self, line):
        return run_octarc(*shlex.split(line)[1:], cwd=self.work)

    def test_every_command_line_runs_and_prints_what_the_readme_shows(self):
        self.assertEqual(readme_commands(), KNOWN)
        # The survey catalog of the second calibration: a multi-level catalog of a field.
        run_octarc("detect", IMAGE, "-c", os.path.join(SOURCE_DIR, "params", "octarc.sex"),
                   "-CATALOG_NAME", "field.ldac", cwd=self.work)
        for line in KNOWN[:4]:
            self.run_line(line)
        for name in ("calibration.fits", "arcs.grid.fits", "arcness.pdf"):
            self.assertTrue(os.path.exists(self.path(name)), name)

        # The calibration figures of 150 000 systems: a study, remade by hand with
        # scripts/readme_studies.py; its reading of the README is checked here.
        self.assertEqual(KNOWN[4:6], readme_studies.COMMANDS)
        with open(README) as f:
            text = f.read()
        for marker, lines, _ in readme_studies.STUDIES:
            commands, printed = readme_studies.blocks_after(text, marker)
            self.assertEqual(commands, lines)
            self.assertTrue(printed and printed[0].startswith("150000 simulated systems"),
                            printed)

        # The two-band run and its colour cut study, then the small run whose study is printed.
        self.run_line(KNOWN[6])
        self.run_line(KNOWN[7])
        run_octarc("simulate", "lenses", "-n", "600", "--seed", "8", "--preset", "dls",
                   "--sigma-min", "300", "--source-mag-min", "21", "--source-mag-max", "23",
                   "--band", "g", "-o", "small-g.fits", "--quiet", cwd=self.work)
        self.assertIn("`-n 600 --seed 8\n--preset dls --sigma-min 300 --source-mag-min 21 "
                      "--source-mag-max 23 --band g`", sections())
        proc = run_octarc("calibrate", "small-g.fits", "-COLOUR_CUT_MAX", "-1,3,0.05",
                          "-CALIBRATION_NAME", "small.fits", "-GRID_NAME", "NONE",
                          "-CHECKPLOT_TYPE", "NONE", cwd=self.work)
        expected = printed_block_after("on this small run")
        out = proc.stdout.splitlines()
        first = out.index(expected[0])
        self.assertEqual(out[first:first + len(expected)], expected)


if __name__ == "__main__":
    unittest.main()
