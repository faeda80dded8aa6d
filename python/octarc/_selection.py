"""octarc.Grid and octarc.Model: the selection of octarc's search, the occupation grid (`octarc
calibrate`, SELECTION_METHOD GRID) and the lens model (SELECTION_METHOD TREES), read from their
files and scoring the rows of a table."""
import numpy as np

from . import _octarc


def _numeric_columns(table, what):
    """The 1-D numeric columns of an astropy Table (or a dict of arrays) as float64 arrays by
    name, masked values as NaN: what octarc's expressions may read."""
    if not hasattr(table, "keys"):
        raise ValueError("%s: an astropy Table or a dict of columns is needed, not %s"
                         % (what, type(table).__name__))
    columns = {}
    for name in table.keys():
        values = table[name]
        array = np.ma.getdata(values)
        if array.ndim != 1 or array.dtype.kind not in "iufb":
            continue
        array = array.astype(np.float64)
        mask = np.ma.getmask(values)
        if mask is not np.ma.nomask and np.any(mask):
            array[np.asarray(mask)] = np.nan
        columns[str(name)] = array
    return columns


# The descriptions of the score columns (dimensionless all).
_SCORE_DESCRIPTIONS = {
    "PROBABILITY": "Occupation probability of the row's grid bin (0 outside the occupied bins)",
    "CONTOUR_LEVEL": "Contour level at which the bin enters (NaN outside the occupied bins)",
    "SELECTED": "The bin is in the grid's contour",
    "GRID_STATUS": "0 occupied bin, 1 empty bin, 2 outside the axes, 3 an axis undefined",
    "LOG_ODDS": "Log-odds of a lens arc, for the model's training mix",
    "LENS_SCORE": "Expected fraction of lens arcs among rows of this score, at the prior given",
}


def _result_table(columns):
    from astropy.table import Column, Table
    return Table([Column(values, name=name, description=_SCORE_DESCRIPTIONS[name])
                  for name, values in columns.items()])


class Grid:
    """An occupation grid (`octarc calibrate -GRID_NAME`): where simulated arcs live in the
    space of its axes, and the contour of bins it selects (METHOD.md section 4). Read one with
    `Grid.read`; give it to `octarc.search(grid=...)` or score a table with `score`."""

    def __init__(self, raw):
        self._raw = raw

    @classmethod
    def read(cls, path):
        """Reads a grid file; a name without a directory that is not in the working directory
        may be one octarc ships (e.g. "demo.grid.fits"). OSError naming the file when it is
        missing or is no grid."""
        return cls(_octarc._read_grid(str(path)))

    @property
    def path(self):
        """The file the grid was read from."""
        return self._raw.path

    @property
    def axes(self):
        """The axes, as (expression, lo, hi, bins) tuples: each covers [lo, hi)."""
        return list(self._raw.axes)

    @property
    def level(self):
        """The contour level P: the selected bins hold at least this fraction of the arcs."""
        return self._raw.level

    @property
    def selected_bins(self):
        """How many bins the contour holds."""
        return self._raw.selected_bins

    @property
    def search_space(self):
        """The search space the grid was made in, (name, cut); empty strings for every arc."""
        return self._raw.search_space

    @property
    def setup(self):
        """The survey setup it was made for: pixel scale and seeing (arcsec), gain, sky sigma
        (ADU), thresholds (sigma), minarea, and the simulation's population file, seed and
        number of systems (NaN or 0 where not recorded)."""
        return self._raw.setup

    def score(self, table):
        """The grid's verdict on every row of `table` (an astropy Table or a dict of arrays
        holding the columns its axes read, e.g. octarc.detect's): an astropy Table, row for row,
        of PROBABILITY (the probability of the row's bin, 0 outside the occupied bins),
        CONTOUR_LEVEL (the level at which the bin enters the contour, NaN outside), SELECTED
        (the bin is in the contour: the search keeps the row, S/N and size aside) and GRID_STATUS
        (0 an occupied bin, 1 an empty bin, 2 outside the axes' ranges, 3 an axis undefined:
        NaN).
        ValueError naming the axis for a column the table lacks."""
        return _result_table(self._raw.score(_numeric_columns(table, "Grid.score")))

    def __repr__(self):
        return "<octarc.Grid %s: %s, P = %g, %d bins selected>" % (
            self.path, ", ".join(a[0] for a in self.axes), self.level, self.selected_bins)


class Model:
    """A lens model (`octarc calibrate -MODEL_NAME`): gradient-boosted trees giving the log-odds
    that a row is a lens arc, from its octopole and shape columns and its context (METHOD.md
    section 4). Read one with `Model.read`; give it to `octarc.search(model=...)` or score a
    table with `score`."""

    def __init__(self, raw):
        self._raw = raw

    @classmethod
    def read(cls, path):
        """Reads a lens model file (a shipped one by its name, e.g. "demo.model.fits").
        OSError naming the file when it is missing or is no model."""
        return cls(_octarc._read_model(str(path)))

    @property
    def path(self):
        """The file the model was read from."""
        return self._raw.path

    @property
    def features(self):
        """The features of a row, in the model's order."""
        return list(self._raw.features)

    @property
    def context_radius(self):
        """How far the context features look for neighbours, arcsec."""
        return self._raw.context_radius

    @property
    def setup(self):
        """The survey setup it was trained for (as `Grid.setup`)."""
        return self._raw.setup

    def score(self, table, *, prior=None, pixel_scale=None, threads=0):
        """The model's verdict on every row of `table` (an astropy Table or a dict of arrays):
        an astropy Table, row for row, of LOG_ODDS (the trees' log-odds of a lens arc, for the
        mix of arcs and other rows they were trained on) and, with `prior`, LENS_SCORE: the
        probability once the odds are moved to rows holding lens arcs at the fraction `prior`
        (0 < prior < 1), as octarc search scores its rows.

        The context features are the table's columns when it holds them (a simulated arcs
        table does), otherwise they are computed from its rows, which must then be every row
        of one image (octarc.detect's, say). pixel_scale: arcsec per pixel, default the model's
        setup's. threads: 0 uses every core; the scores never depend on it. ValueError naming
        a missing column."""
        scale = self.setup["pixel_scale"] if pixel_scale is None else float(pixel_scale)
        if scale != scale:  # NaN: the setup records none
            scale = 0.0
        log_odds = self._raw.log_odds(_numeric_columns(table, "Model.score"), scale,
                                      int(threads))
        columns = {"LOG_ODDS": log_odds}
        if prior is not None:
            columns["LENS_SCORE"] = self._raw.lens_scores(log_odds, float(prior))
        return _result_table(columns)

    def __repr__(self):
        return "<octarc.Model %s: %d features>" % (self.path, len(self.features))
