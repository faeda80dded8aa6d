"""octarc.search: the whole search of an image in memory, as `octarc search` runs it on a file,
with the candidates as an astropy Table."""
import os

from . import (_RunValues, _astropy_table, _config_keys, _header_cards, _image_array,
               _map_array, _mask_array, _octarc)
from ._selection import Grid, Model


class SearchResult(_RunValues):
    """What `search` found: the candidates (`to_table`, the rows of octarc search's
    candidates.fits), every row it searched (`catalog_table`), its summary and warnings."""

    def __init__(self, raw):
        self._raw = raw

    def __len__(self):
        return self._raw.candidates.rows

    def to_table(self, columns=None):
        """The candidates as an astropy Table, best first (LENS_RANK 1 first): the columns
        `columns` (default every column) of octarc search's candidates.fits, with their types,
        units and descriptions. Its meta holds the summary keywords of that file's header
        (NCANDID, SRCHAREA in deg2, CANDDEG2, and per search space SPNAMEn, SPCANDn, ...).
        ValueError for a column name the table lacks."""
        table = _astropy_table(self._raw.candidates, columns)
        for name, value, _ in self._raw.candidates.keywords:
            table.meta[name] = value
        return table

    def catalog_table(self, columns=None):
        """Every row the search looked at (every object at every level, in catalog order) as an
        astropy Table of the PARAMETERS_NAME columns, as `DetectionResult.to_table` gives them.
        A candidate's best row is the row of its THRESH_LEVEL and OBJ_NUMBER (NUMBER here), its
        lens the row of LENS_LEVEL and LENS_NUMBER."""
        return _astropy_table(self._raw.catalog(), columns, "catalog_table")

    def match_injections(self, truth, *, match_radius=None, lens_match_radius=None):
        """Which injected lenses the candidates are arcs of, as `octarc demo` and `octarc
        inject` match them: a candidate is an arc of system S when one of its passing rows lies
        within `match_radius` arcsec of one of S's lensed images (and 1" or more from S's lens);
        it names the right lens when its lens lies within `lens_match_radius` arcsec of S's.

        truth  the field's truth list: an astropy Table with the columns of a .truth.txt file
               (ID, X_IMAGE, Y_IMAGE, ALPHA_J2000, DELTA_J2000, KIND, MAG, THETA_E, SYSTEM), or
               the path of such a file (octarc simulate field, octarc demo).
        match_radius, lens_match_radius  arcsec; default the demo's, 2" and 1".

        Returns (systems, candidate_system): an astropy Table with one row per injected system
        (SYSTEM, THETA_E and ARC_MAG from the truth, CANDIDATE: the row in `to_table()` of the
        first candidate that is one of its arcs, -1 none; SPACES, the candidate's report
        spaces; LENS_RIGHT; THETA_E_ESTIMATE, the candidate's THETA_E, 0 without a lens), and a
        numpy array giving per candidate the system it is an arc of (0: spurious)."""
        import numpy as np
        from astropy.table import Table
        if isinstance(truth, (str, os.PathLike)):
            truth = _read_truth_list(os.fspath(truth))
        columns = {name: np.asarray(truth[name], dtype=float)
                   for name in ("ID", "X_IMAGE", "Y_IMAGE", "ALPHA_J2000", "DELTA_J2000", "KIND",
                                "MAG", "THETA_E", "SYSTEM") if name in truth.keys()}
        match = self._raw.match_injections(
            columns, _octarc._DEMO_ARC_MATCH_ARCSEC if match_radius is None
            else float(match_radius),
            _octarc._DEMO_LENS_MATCH_ARCSEC if lens_match_radius is None
            else float(lens_match_radius))
        return Table(match["systems"]), np.asarray(match["candidate_system"], dtype=int)

    @property
    def summary(self):
        """The summary lines octarc search prints (objects searched, area, candidates per
        search space and per deg2)."""
        return list(self._raw.summary)

    @property
    def warnings(self):
        """The search's warnings: the input's (as `DetectionResult.warnings`), a grid or model
        made for another setup, an image without a WCS."""
        return super().warnings + list(self._raw.warnings)

    @property
    def pixel_scale(self):
        """The pixel scale searched with, arcsec (PIXEL_SCALE, else the WCS's)."""
        return self._raw.pixel_scale


def _read_truth_list(path):
    """A .truth.txt file of octarc simulate field as a dict of columns, named by its
    "# n NAME [unit]" header lines."""
    import numpy as np
    names = []
    with open(path) as f:
        for line in f:
            if not line.startswith("#"):
                break
            words = line[1:].split()
            if len(words) >= 2 and words[0].isdigit() and int(words[0]) == len(names) + 1:
                names.append(words[1])
    if not names:
        raise ValueError("%s: no column header (# 1 ID ...): not a truth list" % path)
    values = np.loadtxt(path, ndmin=2)
    if values.size and values.shape[1] != len(names):
        raise ValueError("%s: %d columns, the header names %d" % (path, values.shape[1],
                                                                   len(names)))
    return {name: values[:, k] if values.size else np.zeros(0) for k, name in enumerate(names)}


def _selector(grid, model):
    if grid is not None and model is not None:
        raise ValueError("search: give a grid or a model, not both")
    if grid is not None:
        return grid._raw if isinstance(grid, Grid) else Grid.read(os.fspath(grid))._raw
    if model is not None:
        return model._raw if isinstance(model, Model) else Model.read(os.fspath(model))._raw
    return None


def search(data, *, grid=None, model=None, weight=None, error=None, mask=None, background=None,
           kernel=None, wcs=None, config_file=None, config=None):
    """Searches `data` for lens candidates, as `octarc search` searches a FITS file: detection
    at every level of the configuration in one pass and every object measured, the rows above
    the S/N floor and resolved selected by the grid or the lens model, one candidate per
    physical object with its lens and Einstein radius, ranked by LENS_SCORE.

    data         2-D image, read as by `detect` (float32/float64 C-contiguous in place).
    grid         an octarc.Grid or a grid file (SELECTION_METHOD GRID).
    model        an octarc.Model or a model file (SELECTION_METHOD TREES). Neither: the
                 configuration's SELECTION_METHOD with its GRID_NAME or MODEL_NAME file.
    weight, error, mask, background, wcs
                 as for `detect` (the WCS gives the candidates' RA, Dec and names, and the
                 searched area in deg2; without one PIXEL_SCALE gives the scale: set it, as
                 its default is SExtractor's 1.0).
    kernel       None: the configuration's FILTER and FILTER_NAME (as the command: SExtractor's
                 default, FILTER Y with default.conv); a .conv file name or a 2-D array.
    config_file  an octarc .sex file read before `config` (e.g. "octarc.sex", the shipped
                 survey configuration: 15 levels from 2.5 to 20 sigma, no filtering); default
                 none. Map files it names are refused: give the maps as arrays.
    config       other keys of `octarc search -dd` by name, e.g. {"PIXEL_SCALE": 0.257,
                 "SNR_MIN": 20, "LENS_LIGHT": "LOCAL", "SEARCH_SPACE": [...]}. PARAMETERS_NAME,
                 when not given, is the shipped column list. COLOUR_IMAGE, MASK_NAME and
                 INPUT_CATALOG name files and are refused here: run octarc search on files.

    Nothing is written (no OUTPUT_DIR, stamps or vetting page). The GIL is released while
    octarc works; Ctrl-C raises KeyboardInterrupt. Returns a SearchResult. ValueError with
    octarc's one-line message for bad input; OSError for a file that cannot be read."""
    if mask is None and hasattr(data, "mask") and hasattr(data, "filled"):
        import numpy as np
        if data.mask is not np.ma.nomask:
            mask = np.ma.getmaskarray(data)
    array, _ = _image_array(data, "data")
    raw = _octarc._search(
        array, _map_array(background, "background"), _map_array(error, "error"),
        _map_array(weight, "weight"), _mask_array(mask), kernel, _header_cards(wcs),
        _config_keys(config), "" if config_file is None else os.fspath(config_file),
        _selector(grid, model))
    return SearchResult(raw)
