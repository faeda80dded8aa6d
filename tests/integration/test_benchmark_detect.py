"""scripts/benchmark-detect.py on a small field: it runs, and its check that octarc detect finds
source-extractor's number of objects at every one of the 15 levels passes (the README's
benchmark claims the same objects at every level)."""
import os
import subprocess
import unittest

from octarc_testlib import OCTARC, SOURCE_DIR, WorkDirTest, require_program


class BenchmarkScript(WorkDirTest):

    def test_small_field_same_objects_at_every_level(self):
        require_program("source-extractor")
        proc = subprocess.run(["/usr/bin/python3",
                               os.path.join(SOURCE_DIR, "scripts", "benchmark-detect.py"),
                               "--octarc", OCTARC, "--workdir", self.work, "--sizes", "600",
                               "--octarc-runs", "1", "--no-sync",
                               "--sex-pixstack", "400000"], capture_output=True, text=True)
        self.assertEqual(proc.returncode, 0, proc.stderr)
        rows = [line for line in proc.stdout.splitlines() if line.startswith("| 600")]
        self.assertEqual(len(rows), 3, proc.stdout)
        counts = {int(line.split("|")[6]) for line in rows}
        self.assertEqual(len(counts), 1, proc.stdout)   # every method, the same rows in all


if __name__ == "__main__":
    unittest.main()
