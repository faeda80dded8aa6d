#!/usr/bin/python3
"""The README's survey-scale study: `octarc batch` on a thousand small tiles, two MPI ranks,
ranks killed at random and the same command run again until the survey is written.

    scripts/survey-scale-study.py [--tiles 1024] [--tile-size 256] [--overlap 16]
                                  [--field-size 2048]
                                  [--kills 5] [--ranks 2] [--seed 1] [--workdir DIR] [--keep]
                                  [--octarc build/release/bin/octarc]

It simulates fields (`octarc simulate field`, 40 lenses each, as tests/integration/test_batch.py
does) and cuts them into tiles of --tile-size pixels, image and weight map, the WCS shifted by
the cut's origin (CRPIX), neighbours sharing --overlap pixels, with a manifest of one tile per
line. It then runs `mpirun -np RANKS octarc batch survey.csv -c params/octarc.sex -GRID_NAME
params/demo.grid.fits -WEIGHT_TYPE MAP_WEIGHT -OUTPUT_DIR out` and, while it runs, sends
SIGKILL to one of its ranks (drawn at random) once the journal has gained a number of `done`
lines drawn at random (up to a quarter of the tiles left over the kills still to make); mpirun
then ends the job, and the same command is run again, --kills times in all, until a run ends
with the survey outputs written. Unless --no-reference, the same batch is then run
uninterrupted into another OUTPUT_DIR.

It then checks that nothing is lost or doubled: the survey catalog is the uninterrupted run's,
column by column; every tile of the manifest has exactly one `done` line in the journal and its
folder (with area.fits); no other tile folder; no temporary (`.NAME.tmp.PID.N`) left anywhere;
the survey catalog's rows are NCANDID = NTILECND - NDUPLIC, NTILECND is both the sum of the
journal's candidate counts and of the rows of the tiles' own candidates.fits, and every (TILE,
TILE_NUMBER) appears once. A failed check is printed under PROBLEMS and ends the script with
status 1.

And it prints the time: the wall time of every run (launch to exit), the start-up of each
(launch to the run's first journal line, and `mpirun -np RANKS /bin/true` alone), the summed
search seconds of the journal's `done` lines, and the bookkeeping per tile,
(wall x ranks - search seconds) / tiles: everything that is not a tile's own search (start-up,
manifest and journal, the work lost to the kills, the survey's merge and pages) spread over the
tiles. With the defaults (16 fields of 2048^2, 1024 tiles of 256^2) it takes about 90 s on two
cores: 45 s making the tiles, 20 s for the killed runs and their reruns, 10 s for the
uninterrupted one."""
import argparse
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time

import numpy as np
from astropy.io import fits

from mpi_ranks import journal, mpi_env, rank_process, temporaries

HERE = os.path.dirname(os.path.abspath(__file__))
PARAMS = os.path.join(HERE, "..", "params")


def make_tiles(octarc, work, tiles, tile_size, overlap, field_size, first_seed):
    """Simulated fields cut into tiles; returns the manifest's path and the tiles' names."""
    step = tile_size - overlap
    names, lines = [], ["image,weight"]
    os.makedirs(os.path.join(work, "tiles"), exist_ok=True)
    seed = first_seed
    while len(names) < tiles:
        field = os.path.join(work, "field%d.fits" % seed)
        subprocess.run([octarc, "simulate", "field", "-o", field, "--size", str(field_size),
                        "--lenses", "40", "--min-einstein-radius", "1.5", "--seed", str(seed),
                        "--quiet"], check=True)
        weight = os.path.join(work, "field%d.weight.fits" % seed)
        with fits.open(field) as f, fits.open(weight) as g:
            for y0 in range(0, field_size - tile_size + 1, step):
                for x0 in range(0, field_size - tile_size + 1, step):
                    if len(names) == tiles:
                        break
                    name = "s%d_x%04d_y%04d" % (seed, x0, y0)
                    for hdu, suffix in ((f[0], ""), (g[0], ".weight")):
                        header = hdu.header.copy()
                        header["CRPIX1"] -= x0
                        header["CRPIX2"] -= y0
                        fits.PrimaryHDU(hdu.data[y0:y0 + tile_size, x0:x0 + tile_size],
                                        header).writeto(
                            os.path.join(work, "tiles", name + suffix + ".fits"))
                    names.append(name)
                    lines.append("tiles/%s.fits,tiles/%s.weight.fits" % (name, name))
        os.remove(field)
        os.remove(weight)
        seed += 1
    manifest = os.path.join(work, "survey.csv")
    with open(manifest, "w") as f:
        f.write("\n".join(lines) + "\n")
    return manifest, names


def run_once(cmd, env, octarc, out, log, kill_at, ranks, rng):
    """One mpirun of the batch; kills a random rank once the journal holds kill_at `done` lines
    (None: no kill). Returns (wall s, start-up s or None, killed rank or None, exit status,
    None or (done lines at the kill, seconds from it to the job's end, done lines since))."""
    before = {e[0] for e in journal(out)}
    t0 = time.time()
    with open(log, "a") as f:
        f.write("$ %s\n" % " ".join(cmd))
        f.flush()
        proc = subprocess.Popen(cmd, stdout=f, stderr=subprocess.STDOUT, env=env)
    startup = None
    killed = None
    done = 0  # `done` lines in the journal
    path, offset = os.path.join(out, "journal.txt"), 0
    while proc.poll() is None:
        # Only the whole lines appended since the last look are read.
        if os.path.exists(path):
            with open(path, "rb") as f:
                f.seek(offset)
                chunk = f.read()
            chunk = chunk[:chunk.rfind(b"\n") + 1]
            offset += len(chunk)
            for line in chunk.decode().splitlines():
                fields = line.split("\t")
                if len(fields) != 5:
                    continue
                if startup is None and fields[0] not in before:
                    startup = time.time() - t0
                done += fields[2] == "done"
        if kill_at is not None and killed is None and done >= kill_at:
            rank = rng.randrange(ranks)
            pid = rank_process(octarc, out, rank)
            if pid:
                os.kill(pid, signal.SIGKILL)
                killed = rank
                kill_time = time.time()
                at_kill = done
        time.sleep(0.02)
    wall = time.time() - t0
    after = None
    if killed is not None:
        # How long the job took to end after the kill, and the tiles journaled meanwhile.
        after = (at_kill, time.time() - kill_time,
                 len([e for e in journal(out) if e[2] == "done"]) - at_kill)
    if startup is None and any(e[0] not in before for e in journal(out)):
        startup = wall
    return wall, startup, killed, proc.returncode, after


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--tiles", type=int, default=1024)
    ap.add_argument("--tile-size", type=int, default=256)
    ap.add_argument("--overlap", type=int, default=16,
                    help="pixels shared by neighbouring tiles, whose candidates the merge "
                    "counts once")
    ap.add_argument("--field-size", type=int, default=2048)
    ap.add_argument("--kills", type=int, default=5)
    ap.add_argument("--ranks", type=int, default=2)
    ap.add_argument("--seed", type=int, default=1, help="the kills' random draws")
    ap.add_argument("--first-field-seed", type=int, default=501)
    ap.add_argument("--workdir", help="default: a temporary folder, removed unless --keep")
    ap.add_argument("--keep", action="store_true")
    ap.add_argument("--no-reference", dest="reference", action="store_false",
                    help="skip the uninterrupted run that the survey catalog is compared with")
    ap.add_argument("--octarc", default=os.path.join(HERE, "..", "build", "release", "bin",
                                                     "octarc"))
    args = ap.parse_args()
    octarc = os.path.abspath(args.octarc)
    rng = random.Random(args.seed)
    work = args.workdir or tempfile.mkdtemp(prefix="octarc-survey-scale-")
    os.makedirs(work, exist_ok=True)
    env = mpi_env()

    t = time.time()
    manifest, names = make_tiles(octarc, work, args.tiles, args.tile_size, args.overlap,
                                 args.field_size,
                                 args.first_field_seed)
    print("%d tiles of %d^2 (overlap %d) from %d^2 fields in %s (%.0f s)"
          % (len(names), args.tile_size, args.overlap, args.field_size, work, time.time() - t))

    bare = []
    for _ in range(3):
        t = time.time()
        subprocess.run(["mpirun", "--oversubscribe", "-np", str(args.ranks), "/bin/true"],
                       env=env, check=True)
        bare.append(time.time() - t)

    out = os.path.join(work, "out")
    log = os.path.join(work, "batch.log")
    cmd = ["mpirun", "--oversubscribe", "-np", str(args.ranks), octarc, "batch", manifest,
           "-c", os.path.join(PARAMS, "octarc.sex"),
           "-GRID_NAME", os.path.join(PARAMS, "demo.grid.fits"), "-WEIGHT_TYPE", "MAP_WEIGHT",
           "-OUTPUT_DIR", out]
    runs = []
    kills = 0
    problems = []
    while True:
        done = len({e[3] for e in journal(out) if e[2] == "done"})
        left = len(names) - done
        kill_at = None
        if kills < args.kills and left > 1:
            # A kill early in what is left, so that every kill finds tiles still to search: the
            # other ranks go on searching until mpirun has ended the job (some 30-60 tiles of
            # 256^2 in the small trial).
            span = max(1, left // (4 * (args.kills - kills)))
            kill_at = done + rng.randint(1, span)
        wall, startup, killed, status, after = run_once(cmd, env, octarc, out, log, kill_at,
                                                 args.ranks, rng)
        now = {e[3] for e in journal(out) if e[2] == "done"}
        runs.append((wall, startup, killed, status, len(now) - done))
        print("run %d: %.1f s, start-up %s, %d tiles done, %s, exit %d"
              % (len(runs), wall, "%.2f s" % startup if startup is not None else "-",
                 len(now) - done, "rank %d killed at %d done (the job ended %.2f s later, "
                 "%d more journaled)" % ((killed,) + after) if killed is not None
                 else "no kill", status), flush=True)
        if killed is not None:
            kills += 1
            if status == 0:
                problems.append("run %d ended with status 0 after its rank %d was killed"
                                % (len(runs), killed))
            continue
        if status != 0:
            problems.append("run %d, not killed, ended with status %d (see %s)"
                            % (len(runs), status, log))
        break

    # Nothing lost or doubled.
    events = journal(out)
    done_lines = {}
    seconds = 0.0
    journal_candidates = 0
    for run, _, event, tile, detail in events:
        if event == "done":
            done_lines.setdefault(tile, []).append(run)
            m = re.match(r"(\d+) candidates, ([\d.]+) s, rank (\d+)$", detail)
            journal_candidates += int(m.group(1))
            seconds += float(m.group(2))
        elif event == "failed":
            problems.append("tile %s failed in run %s: %s" % (tile, run, detail))
    doubled = {t: r for t, r in done_lines.items() if len(r) != 1}
    missing = sorted(set(names) - set(done_lines))
    if doubled:
        problems.append("tiles done more than once: %s" % doubled)
    if missing:
        problems.append("tiles without a done line: %s" % missing)
    folders = set(os.listdir(os.path.join(out, "tiles"))) if os.path.isdir(
        os.path.join(out, "tiles")) else set()
    if folders != set(names):
        problems.append("tile folders missing %s, extra %s"
                        % (sorted(set(names) - folders), sorted(folders - set(names))))
    incomplete = [n for n in names if not os.path.exists(os.path.join(out, "tiles", n,
                                                                      "area.fits"))]
    if incomplete:
        problems.append("tile folders without area.fits: %s" % incomplete)
    left_over = temporaries(work)
    if left_over:
        problems.append("temporaries left: %s" % left_over)
    tile_rows = 0
    for n in names:
        path = os.path.join(out, "tiles", n, "candidates.fits")
        if os.path.exists(path):
            with fits.open(path) as f:
                tile_rows += len(f["LDAC_OBJECTS"].data)
    survey = os.path.join(out, "candidates.fits")
    rows = ntilecnd = nduplic = ncandid = None
    if os.path.exists(survey):
        with fits.open(survey) as f:
            data, header = f["LDAC_OBJECTS"].data, f["LDAC_OBJECTS"].header
            rows = len(data)
            ncandid, ntilecnd, nduplic = header["NCANDID"], header["NTILECND"], header["NDUPLIC"]
            if header["NTILES"] != len(names):
                problems.append("NTILES %d, manifest %d" % (header["NTILES"], len(names)))
            keys = set(zip((str(s).strip() for s in data["TILE"]), data["TILE_NUMBER"]))
            if len(keys) != rows:
                problems.append("a (TILE, TILE_NUMBER) appears twice in the survey catalog")
        if not (rows == ncandid == ntilecnd - nduplic and ntilecnd == journal_candidates
                == tile_rows):
            problems.append("rows %d, NCANDID %d, NTILECND %d, NDUPLIC %d, journal %d, tiles %d"
                            % (rows, ncandid, ntilecnd, nduplic, journal_candidates, tile_rows))
    else:
        problems.append("no survey catalog")

    # The same batch uninterrupted, into another OUTPUT_DIR: the same survey catalog, column by
    # column, and the bookkeeping without kills.
    reference = None
    if args.reference:
        ref_out = os.path.join(work, "reference")
        ref_cmd = [ref_out if a == out else a for a in cmd]
        ref_wall, ref_startup, _, ref_status, _ = run_once(ref_cmd, env, octarc, ref_out, log, None,
                                                        args.ranks, rng)
        ref_seconds = sum(float(re.match(r"\d+ candidates, ([\d.]+) s", e[4]).group(1))
                          for e in journal(ref_out) if e[2] == "done")
        reference = (ref_wall, ref_startup, ref_seconds)
        if ref_status != 0:
            problems.append("the uninterrupted run ended with status %d" % ref_status)
        elif os.path.exists(survey):
            with fits.open(survey) as f, fits.open(os.path.join(ref_out, "candidates.fits")) as g:
                a, b = f["LDAC_OBJECTS"].data, g["LDAC_OBJECTS"].data
                same = a.columns.names == b.columns.names and len(a) == len(b) and all(
                    np.array_equal(a[c], b[c], equal_nan=a[c].dtype.kind == "f")
                    for c in a.columns.names)
                if not same:
                    problems.append("the survey catalog differs from the uninterrupted run's")

    total_wall = sum(r[0] for r in runs)
    bookkeeping = (total_wall * args.ranks - seconds) / len(names)
    startups = [r[1] for r in runs if r[1] is not None]
    print()
    print("tiles: %d of %d^2 pixels, %d ranks" % (len(names), args.tile_size, args.ranks))
    print("kills: %d of %d asked (ranks %s), runs: %d (%d reruns)"
          % (kills, args.kills, ",".join(str(r[2]) for r in runs if r[2] is not None), len(runs),
             len(runs) - 1))
    print("tiles done per run: %s" % ", ".join(str(r[4]) for r in runs))
    print("done lines: %d for %d tiles, each tile once: %s; folders: %d; temporaries left: %d"
          % (sum(len(r) for r in done_lines.values()), len(names), not doubled and not missing,
             len(folders), len(left_over)))
    if rows is not None:
        print("candidates: %d in the tiles (journal %d, tiles' catalogs %d), %d duplicates "
              "removed, %d in the survey (NCANDID %d)"
              % (ntilecnd, journal_candidates, tile_rows, nduplic, rows, ncandid))
    print("wall: %.1f s in all runs (%s)" % (total_wall,
                                              ", ".join("%.1f" % r[0] for r in runs)))
    print("start-up per run (launch to its first journal line): mean %.2f s, max %.2f s; "
          "mpirun -np %d /bin/true: %.2f s"
          % (np.mean(startups) if startups else float("nan"),
             max(startups) if startups else float("nan"), args.ranks, float(np.median(bare))))
    print("search: %.1f s summed over the journal's done lines, %.3f s per tile"
          % (seconds, seconds / len(names)))
    print("bookkeeping: (%.1f s x %d - %.1f s) / %d = %.3f s per tile (%.0f %% of the search)"
          % (total_wall, args.ranks, seconds, len(names), bookkeeping,
             100 * bookkeeping / (seconds / len(names))))
    if reference:
        ref_wall, ref_startup, ref_seconds = reference
        ref_book = (ref_wall * args.ranks - ref_seconds) / len(names)
        print("uninterrupted run: %.1f s wall, start-up %.2f s, search %.1f s, bookkeeping "
              "%.3f s per tile (%.0f %% of the search); survey catalog the same: %s"
              % (ref_wall, ref_startup or float("nan"), ref_seconds, ref_book,
                 100 * ref_book / (ref_seconds / len(names)),
                 not any("uninterrupted" in p for p in problems)))
    if problems:
        print("\nPROBLEMS:")
        for p in problems:
            print("  " + p)
    if not args.keep and not args.workdir and not problems:
        shutil.rmtree(work)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
