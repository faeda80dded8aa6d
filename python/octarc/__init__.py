"""octarc in Python: SExtractor-compatible detection at many thresholds in one pass and octarc's
measurements (isophotal photometry and shape, the octopole "arcness" moments) on numpy arrays,
with astropy tables out; octarc's simulations of galaxy-galaxy lenses and survey fields; and
its selection and search for strong-lens arcs.

    >>> import octarc
    >>> found = octarc.detect(image, [2.5, 5.0, 10.0])     # thresholds in units of sigma
    >>> table = found.to_table()                            # astropy Table, units from octarc
    >>> labels = found.segmentation(1)                      # int32 labels of the lowest level

    >>> lenses = octarc.simulate_lenses(100, seed=1)        # octarc simulate lenses
    >>> field = octarc.simulate_field(1024, lenses=5)       # octarc simulate field

    >>> result = octarc.search(field.image, weight=field.weight, wcs=field.header,
    ...                        model="demo.model.fits", config_file="octarc.sex")
    >>> candidates = result.to_table()                      # octarc search's candidates.fits
    >>> systems, _ = result.match_injections(field.truth)   # the injected lenses found

The work is done by octarc's libraries, the same calls as the `octarc detect`, `octarc
measure`, `octarc simulate` and `octarc search` commands make: the same arrays give the same
numbers as the commands on a FITS file holding them, and the same seed and options the same
simulation. The GIL is released while octarc works, Ctrl-C interrupts a call
(KeyboardInterrupt), and octarc's one-line errors arrive as ValueError (bad input) or OSError
(a file). See docs/python.md.
"""
import numbers
import os

import numpy as np

from . import _octarc

__all__ = ["detect", "measure", "simulate_lenses", "simulate_field", "inject_lenses",
           "search", "Grid", "Model", "DetectionResult", "MeasurementResult",
           "LensSimulation", "SimulatedField", "SearchResult", "__version__"]

#: octarc's version (the same as `octarc -v`).
__version__ = _octarc.__version__

_FLOAT_TYPES = (np.dtype(np.float32), np.dtype(np.float64))


def _shipped_data_directory():
    """octarc's data directory (share/octarc: octarc.sex, default.conv, ...) for this package:
    <prefix>/share/octarc for a package in <prefix>/lib/python3*/*-packages/octarc, and
    <build>/share/octarc in a build tree (<build>/python/octarc); None when neither holds it."""
    here = os.path.dirname(os.path.abspath(__file__))
    for levels in (4, 2):
        candidate = os.path.normpath(os.path.join(here, *[".."] * levels, "share", "octarc"))
        if os.path.isfile(os.path.join(candidate, "octarc.sex")):
            return candidate
    return None


# The libraries look for their data files beside the running executable, which is python3 here.
if _shipped_data_directory() is not None:
    _octarc._set_data_directory(_shipped_data_directory())


def _image_array(values, what):
    """`values` as a 2-D C-contiguous float32/float64 array: the array itself when it is one
    (octarc reads it in place), otherwise converted once to float32. Returns (array, converted)."""
    array = np.asarray(values)
    if array.dtype.kind not in "iuf":
        raise ValueError("%s: dtype %s is not a real number type" % (what, array.dtype))
    if array.ndim != 2:
        raise ValueError("%s: a 2-D array is needed, not one of %d dimension(s)"
                         % (what, array.ndim))
    if array.dtype in _FLOAT_TYPES and array.dtype.isnative and array.flags.c_contiguous:
        return array, False
    return np.ascontiguousarray(array, dtype=np.float32), True


def _map_array(values, what):
    """A number stays a number; an array is made 2-D float32/float64 C-contiguous."""
    if values is None or isinstance(values, numbers.Real):
        return None if values is None else float(values)
    return _image_array(values, what)[0]


def _mask_array(mask):
    if mask is None:
        return None
    array = np.asarray(mask)
    if array.ndim != 2:
        raise ValueError("mask: a 2-D array is needed, not one of %d dimension(s)" % array.ndim)
    return np.ascontiguousarray(array, dtype=bool)


def _header_cards(wcs):
    """The FITS header cards of `wcs`: an astropy WCS, an astropy Header or a header's text."""
    if wcs is None:
        return []
    if hasattr(wcs, "to_header"):
        wcs = wcs.to_header()
    if hasattr(wcs, "cards"):
        # A long string's card comes as several 80-character cards (CONTINUE) in one image.
        return [card.image[i:i + 80] for card in wcs.cards
                for i in range(0, len(card.image), 80)]
    if isinstance(wcs, str):
        text = wcs.rstrip()
        cards = [text[i:i + 80].ljust(80) for i in range(0, len(text), 80)]
        return [c for c in cards if not c.startswith("END ") and c.strip()]
    raise ValueError("wcs: an astropy WCS, an astropy Header or a header's text is needed, not %s"
                     % type(wcs).__name__)


def _thresholds(thresholds, default):
    if thresholds is None:
        return default
    if isinstance(thresholds, numbers.Real):
        return [float(thresholds)]
    return [float(t) for t in thresholds]


def _relative(thresh_type):
    kind = str(thresh_type).upper()
    if kind not in ("RELATIVE", "ABSOLUTE"):
        raise ValueError("thresh_type: RELATIVE or ABSOLUTE, not %r" % (thresh_type,))
    return kind == "RELATIVE"


def _config_keys(config):
    """octarc configuration keys (SExtractor's names) as (KEY, value) pairs."""
    keys = []
    for key, value in (config or {}).items():
        if isinstance(value, (list, tuple)):
            value = ",".join(repr(float(v)) if isinstance(v, float) else str(v) for v in value)
        elif isinstance(value, bool):
            value = "Y" if value else "N"
        elif isinstance(value, float):
            value = repr(value)
        keys.append((str(key).upper(), str(value)))
    return keys


def _unit(text):
    from astropy import units as u
    return u.Unit(text, parse_strict="silent") if text else None


def _astropy_table(raw, columns=None, what="to_table"):
    """An astropy Table of octarc table `raw` (`_octarc._Table`, or a `_FitsTable` made in
    memory) with the columns `columns` (names, in that order; None: every column), each of its
    storage type, with the unit, description and, where declared, UCD (in the column's meta) of
    octarc's declaration. ValueError, naming `what`, for a name it lacks."""
    from astropy.table import Column, Table
    specs = {c["name"]: c for c in raw.columns}
    names = list(specs) if columns is None else list(columns)
    for name in names:
        if name not in specs:
            raise ValueError("%s: the table has no column %s" % (what, name))
    table = Table()
    for name in names:
        spec = specs[name]
        meta = {"ucd": spec["ucd"]} if "ucd" in spec else {}
        table[name] = Column(raw.column(name), name=name, unit=_unit(spec["unit"]),
                             description=spec["description"], meta=meta)
    return table


class _RunValues:
    """What every result of a detection (detect, measure, search) tells of its run: the
    thresholds, the background and noise, the warnings."""

    @property
    def thresholds(self):
        """The threshold of each level in ADU, lowest first (a numpy array)."""
        return np.array(self._raw.thresholds)

    @property
    def background(self):
        """The background level in ADU (the global level for a mesh background)."""
        return self._raw.values["background"]

    @property
    def sigma(self):
        """The global noise sigma in ADU (the unit of RELATIVE thresholds)."""
        return self._raw.values["sigma"]

    @property
    def warnings(self):
        """octarc's warnings: about the configuration (an unknown or ignored key of a .sex
        file) and the input (constant image, bad meshes...)."""
        return list(self._raw.values["warnings"])


class _TableResult(_RunValues):
    """What detect and measure results share: the catalog table and the run's values."""

    def __init__(self, raw):
        self._raw = raw
        self._columns = {c["name"]: c for c in raw.table.columns}

    @property
    def column_names(self):
        """The names of every column octarc measured, in its order."""
        return list(self._columns)

    def __len__(self):
        return self._raw.table.rows

    def column(self, name):
        """The values of one column as a numpy array of the type octarc's catalogs store it in;
        ValueError for a name octarc does not measure."""
        return self._raw.table.column(name)

    def to_table(self, columns=None):
        """An astropy Table of the rows, with the columns `columns` (names, in that order;
        default every column) as octarc's catalogs hold them: the same storage types, and the
        units, descriptions and UCDs (in each column's meta) of octarc's column declarations.
        The table's meta holds the background, sigma and thresholds (ADU).
        ValueError for a column name octarc does not measure."""
        table = _astropy_table(self._raw.table, columns, "to_table")
        table.meta["BACKGROUND"] = self.background
        table.meta["SIGMA"] = self.sigma
        table.meta["THRESHOLDS"] = list(self._raw.thresholds)
        return table


class DetectionResult(_TableResult):
    """What `detect` found: one row per object per level (`to_table`), the thresholds, the
    background and noise, and the segmentation of every level (`segmentation`)."""

    def __init__(self, raw, data, converted):
        super().__init__(raw)
        self._data = data
        #: True when `data` was not a C-contiguous float32/float64 array and was converted
        #: once to float32 before octarc read it; False when octarc read the caller's array
        #: itself (no copy before octarc's own working image).
        self.data_converted = converted

    @property
    def objects_per_level(self):
        """The number of objects at each level, lowest first (a list)."""
        return list(self._raw.objects_per_level)

    @property
    def data(self):
        """The array octarc read: the caller's own when `data_converted` is False."""
        return self._data

    def segmentation(self, level=1):
        """The labels of level `level` (1 = lowest) as an int32 array of the image's shape:
        each object's NUMBER on its pixels, 0 elsewhere (SExtractor's SEGMENTATION check-image
        of that threshold). ValueError when the run kept none (segmentation=False)."""
        return self._raw.segmentation(level)


class MeasurementResult(_TableResult):
    """What `measure` measured: one row per object per level (`to_table`), or, with a
    `catalog`, that catalog's rows with octarc's columns appended."""

    def __init__(self, raw, catalog):
        super().__init__(raw)
        self._catalog = catalog

    def to_table(self, columns=None):
        """As `DetectionResult.to_table`. With the `catalog` given to `measure`, its rows and
        columns come first, joined by NUMBER, followed by octarc's columns (those of `columns`,
        default every column) that the catalog lacks, as `octarc measure` appends them."""
        table = super().to_table(columns)
        if self._catalog is None:
            return table
        catalog = self._catalog.copy()
        numbers_here = np.asarray(table["NUMBER"]) if "NUMBER" in table.colnames else \
            np.asarray(self._raw.table.column("NUMBER"))
        row_of = {int(n): i for i, n in enumerate(numbers_here)}
        wanted = np.asarray(catalog["NUMBER"])
        missing = [int(n) for n in wanted if int(n) not in row_of]
        if missing:
            raise ValueError("catalog: NUMBER %d has no object in the segmentation" % missing[0])
        if len(wanted) != len(row_of):
            extra = sorted(set(row_of) - set(int(n) for n in wanted))
            raise ValueError("catalog: label %d of the segmentation has no row" % extra[0])
        order = np.array([row_of[int(n)] for n in wanted], dtype=int)
        for name in table.colnames:
            if name not in catalog.colnames:
                catalog[name] = table[name][order]
        return catalog


def detect(data, thresholds=None, *, background=None, error=None, mask=None, weight=None,
           minarea=5, kernel=None, wcs=None, thresh_type="RELATIVE", segmentation=True,
           config=None):
    """Detects the objects of `data` at every threshold in one pass, without deblending, and
    measures every object of every level, as `octarc detect` does.

    data        2-D image (rows = y, NAXIS2). A C-contiguous float32 or float64 array is read
                in place; any other real array is converted once to float32 first (see
                `DetectionResult.data_converted`). octarc works on its own float32 copy with
                the background subtracted; `data` is never modified.
    thresholds  the detection thresholds, lowest first: a number or a sequence, in units of
                the noise sigma (thresh_type RELATIVE, SExtractor's default) or ADU
                (ABSOLUTE). Default 1.5 (SExtractor's DETECT_THRESH). Each level's isophote is
                its own threshold (one level: ANALYSIS_THRESH = DETECT_THRESH).
    background  None: estimated on meshes (BACK_TYPE AUTO, BACK_SIZE 64, BACK_FILTERSIZE 3);
                a number: that constant level (BACK_TYPE MANUAL); an array: that map,
                subtracted (BACKGROUND_NAME).
    error       None: the noise sigma from the background estimate; a number: the noise
                sigma in ADU; an array: per-pixel RMS noise (WEIGHT_TYPE MAP_RMS), which
                the RELATIVE thresholds then follow pixel by pixel.
    mask        boolean array, True where pixels are bad: they are blank (NaN) for octarc,
                never part of an object or of the background (default: the mask of a numpy
                masked array `data`).
    weight      relative weights (inverse variance; WEIGHT_TYPE MAP_WEIGHT); not with an
                error array.
    minarea     the least number of pixels of an object (DETECT_MINAREA).
    kernel      None: no filtering (FILTER N, unlike SExtractor's default); a .conv file name
                (FILTER_NAME, also looked up among SExtractor's); a 2-D array, normalised as
                a .conv file with NORM is.
    wcs         an astropy WCS or Header (or a header's text): the WCS of ALPHA_J2000 ...,
                and GAIN and SATURATE keywords as in a FITS file's header.
    thresh_type "RELATIVE" or "ABSOLUTE" (THRESH_TYPE).
    segmentation keep every level's labels for `DetectionResult.segmentation`.
    config      other octarc configuration keys by their SExtractor names, e.g.
                {"GAIN": 4.0, "MAG_ZEROPOINT": 30, "BACK_SIZE": 128, "NTHREADS": 1}
                (`octarc detect -dd` lists them; NTHREADS 0, the default, uses every core,
                and the results never depend on it).

    Returns a DetectionResult. ValueError with octarc's one-line message for bad input (wrong
    dtype or shape, an image without a finite pixel, a map whose shape differs, thresholds not
    increasing, a bad key); OSError for a kernel file that cannot be read."""
    if mask is None and isinstance(data, np.ma.MaskedArray) and data.mask is not np.ma.nomask:
        mask = np.ma.getmaskarray(data)
    array, converted = _image_array(data, "data")
    raw = _octarc._detect(
        array, _thresholds(thresholds, [1.5]), _relative(thresh_type), int(minarea),
        _map_array(background, "background"), _map_array(error, "error"),
        _map_array(weight, "weight"), _mask_array(mask), kernel, _header_cards(wcs),
        _config_keys(config), bool(segmentation))
    return DetectionResult(raw, array, converted)


def _label_arrays(segmentation):
    """The label images, lowest level first, each int32 C-contiguous."""
    if isinstance(segmentation, np.ndarray) and segmentation.ndim == 2:
        levels = [segmentation]
    elif isinstance(segmentation, np.ndarray) and segmentation.ndim == 3:
        levels = list(segmentation)
    elif isinstance(segmentation, (list, tuple)):
        levels = [np.asarray(s) for s in segmentation]
    else:
        raise ValueError("segmentation: a 2-D label image, a 3-D stack or a list of them is "
                         "needed")
    out = []
    for k, level in enumerate(levels):
        if level.dtype.kind not in "iu":
            raise ValueError("segmentation[%d]: dtype %s is not an integer type" % (k, level.dtype))
        out.append(np.ascontiguousarray(level, dtype=np.int32))
    return out


def measure(data, segmentation, *, catalog=None, thresholds=None, background=None, error=None,
            mask=None, weight=None, kernel=None, wcs=None, thresh_type="RELATIVE", config=None):
    """Measures the objects of given segmentation images with octarc's columns, as `octarc
    measure` does with SExtractor's SEGMENTATION check-images.

    data          2-D image, read as by `detect`.
    segmentation  one label image (0 = no object, > 0 = NUMBER), or a list or 3-D stack of
                  them, one per threshold, lowest first; the levels must nest.
    catalog       an astropy Table of the SExtractor run of a single level (with NUMBER): the
                  result's table is then that catalog with octarc's columns appended, rows
                  joined by NUMBER (every label must have its row and every row its label).
    thresholds    each level's threshold (THRESH_TYPE units, as `detect`); needed with several
                  levels; default for one level 1.5, SExtractor's ANALYSIS_THRESH.
    background, error, mask, weight, kernel, wcs, thresh_type, config
                  as for `detect` (the kernel gives the filtered image that SExtractor's
                  filtered columns use).

    Returns a MeasurementResult. ValueError for bad input (as `detect`, and label images that
    do not nest or differ in shape from `data`)."""
    array, _ = _image_array(data, "data")
    if catalog is not None and "NUMBER" not in catalog.colnames:
        raise ValueError("catalog: no NUMBER column")
    levels = _label_arrays(segmentation)
    if catalog is not None and len(levels) != 1:
        raise ValueError("catalog: only with the segmentation of a single level")
    threshold_list = None if thresholds is None else _thresholds(thresholds, None)
    raw = _octarc._measure(
        array, levels, threshold_list, _relative(thresh_type),
        _map_array(background, "background"), _map_array(error, "error"),
        _map_array(weight, "weight"), _mask_array(mask), kernel, _header_cards(wcs),
        _config_keys(config))
    return MeasurementResult(raw, catalog)


def _warn(messages):
    """octarc's warnings about a .sex file, as Python warnings (the commands print them)."""
    import warnings
    for message in messages:
        warnings.warn(message, stacklevel=3)


def _colour(value, what):
    """A colour draw as octarc's "MEAN,SCATTER" text: from a (mean, scatter) pair or the text."""
    if value is None or isinstance(value, str):
        return value
    pair = list(value)
    if len(pair) != 2:
        raise ValueError("%s: (mean, scatter) in mag, not %d value(s)" % (what, len(pair)))
    return "%r,%r" % (float(pair[0]), float(pair[1]))


def _natural(value, what, maximum=2 ** 31 - 1, minimum=0):
    """`value` as an int in [minimum, maximum] (counts are C ints, seeds unsigned 64-bit
    numbers)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or not \
            minimum <= value <= maximum:
        raise ValueError("%s: an integer from %d to %d is needed, not %r"
                         % (what, minimum, maximum, value))
    return int(value)


def _python_names(call, *args):
    """`call(*args)`, octarc's ValueError messages naming the command's options (--pixel-scale)
    by this module's keywords (pixel_scale), which the simulations take with the same names."""
    import re
    try:
        return call(*args)
    except ValueError as error:
        text = re.sub(r"(?<![\w-])--([a-z][a-z0-9-]*)",
                      lambda m: m.group(1).replace("-", "_"), str(error))
        raise ValueError(text) from None


def _card_values(cards):
    """{keyword: value} of FITS header cards, in their order."""
    from astropy.io import fits
    return {card.keyword: card.value for card in map(fits.Card.fromstring, cards)}


class LensSimulation:
    """What `simulate_lenses` made: the systems table (`to_table`), the arc table
    (`arcs_table`), the stamps of the first systems and the run's counts."""

    def __init__(self, raw):
        self._raw = raw
        counts = raw.counts
        #: Systems drawn from the population (the n of the call).
        self.drawn = counts["drawn"]
        #: Systems rendered (rows of the systems table; fewer than drawn with importance
        #: sampling, the others stood for by the weights SIM_WEIGHT).
        self.rendered = counts["rendered"]
        #: Rendered systems with an arc (ARC_FOUND 1).
        self.systems_with_arc = counts["systems_with_arc"]
        #: Systems skipped below the population's Einstein radius limit.
        self.skipped = counts["skipped"]
        #: The sum of SIM_WEIGHT over the rendered systems.
        self.weight_sum = counts["weight_sum"]
        #: Kish's effective number of arcs, (sum w)^2 / sum w^2 over the systems with an arc.
        self.effective_arcs = counts["effective_arcs"]
        #: The OCT* keywords of the command's catalog header (seed, counts, survey, levels,
        #: source database) as {keyword: value}.
        self.meta = _card_values(raw.cards)

    def __len__(self):
        return self.rendered

    @property
    def stamps(self):
        """The stamps of the first `stamps` systems drawn (plane k is system k; zeros for a
        system that importance sampling did not render, as in the command's stamps file),
        background-subtracted ADU, as a read-only float32 array of shape (stamps, side, side)
        (a view of the one block the stamps were gathered in, no copy)."""
        return self._raw.stamps

    def to_table(self, columns=None):
        """The systems table (LDAC_OBJECTS of `octarc simulate lenses`' catalog) as an astropy
        Table: one row per rendered system, truth, SIM_WEIGHT, ARC_FOUND and the chosen arc's
        measurements, with the columns `columns` (names, in that order; default every column),
        storage types, units, descriptions and UCDs of octarc's declarations; the table's meta
        holds `meta`. ValueError for a name the table lacks."""
        table = _astropy_table(self._raw.systems, columns, "to_table")
        table.meta.update(self.meta)
        return table

    def arcs_table(self, columns=None):
        """The arc table (ARCS of the command's catalog): every arc row at every level, SYSTEM
        the row's system, as `to_table`. ValueError for a name the table lacks."""
        table = _astropy_table(self._raw.arcs, columns, "arcs_table")
        table.meta.update(self.meta)
        return table


def simulate_lenses(n, *, seed=1, preset="dls", setup=None, database=None, sources=90,
                    source_extent=4.0, sampling="importance", stamps=0, threads=0, band=None,
                    source_colour=None, lens_colour=None):
    """Simulates `n` galaxy-galaxy lenses, detects every stamp at the survey's thresholds,
    measures every object and applies the arc rules, as `octarc simulate lenses` does; the
    tables are those of its catalog, in memory.

    n             the number of systems drawn (> 0).
    seed          the master seed (an integer >= 0): the result depends on it alone, never on
                  `threads`.
    preset        the lens population: "dls" (the Deep Lens Survey ranges) or "physical" (a
                  measured velocity dispersion function, the command's default); None with
                  setup["population"], a population file of one's own.
    setup         the survey and population options of the command by their long names, '-'
                  as '_': pixel_scale, seeing, gain, zero_point, sky_sigma, limiting_mag,
                  stamp_size, thresh, thresh_max, nlevels, minarea, lens_mag_min/max,
                  source_mag_min/max, sigma_min/max, lens_e_max, lens_rhalf_min/max,
                  fine_scale, subsamples, max_source_step, population (a file), and "config":
                  a survey .sex file, which the other keys override.
    database      a RealGalaxyCatalog FITS table of source galaxies; None: `sources` synthetic
                  galaxies reaching `source_extent` half-light radii.
    sampling      "importance" (render the systems likely to give an arc, weighted back:
                  SIM_WEIGHT) or "plain" (render every system).
    stamps        keep the stamps of the first `stamps` systems (`LensSimulation.stamps`).
    threads       worker threads (0: every core).
    band          a second band's name (e.g. "g"), with `source_colour` and `lens_colour`
                  (mean, scatter) in mag (defaults 0.4, 0.3 and 1.2, 0.1).

    Returns a LensSimulation. ValueError with octarc's one-line message for a bad value or an
    unknown setup key; OSError for a file that cannot be read. Ctrl-C interrupts the call."""
    if setup is None:
        setup = {}
    if not isinstance(setup, dict):
        raise ValueError("setup: a dict of options is needed, not %s" % type(setup).__name__)
    raw = _python_names(
        _octarc._simulate_lenses,
        _natural(n, "n", 2 ** 63 - 1), _natural(seed, "seed", 2 ** 64 - 1),
        "" if preset is None else str(preset), setup,
        "" if database is None else os.fspath(database), _natural(sources, "sources", minimum=1),
        float(source_extent), str(sampling), _natural(stamps, "stamps"),
        _natural(threads, "threads"), None if band is None else str(band),
        _colour(source_colour, "source_colour"),
        _colour(lens_colour, "lens_colour"))
    _warn(raw.warnings)
    return LensSimulation(raw)


class SimulatedField:
    """What `simulate_field` (or `inject_lenses`) made: `image` and `weight` (float32 arrays),
    `header` (an astropy Header with the WCS), `truth` (an astropy Table) and `sky_sigma`."""

    def __init__(self, raw):
        from astropy.io import fits
        #: The image, ADU, sky subtracted (float32; FIELD.fits of the command).
        self.image = raw.image
        #: The weight map, 1 / variance in ADU^-2, the chip gap at half weight (float32;
        #: FIELD.weight.fits).
        self.weight = raw.weight
        #: The image's FITS header: the TAN WCS and the survey keywords.
        self.header = fits.Header([fits.Card.fromstring(card) for card in raw.header_cards])
        #: The per-pixel sky noise sigma, ADU.
        self.sky_sigma = raw.sky_sigma
        counts = raw.counts
        #: The number of field galaxies.
        self.galaxy_count = counts["galaxies"]
        #: The number of stars.
        self.star_count = counts["stars"]
        #: The number of pixels clipped at the saturation level.
        self.saturated_pixels = counts["saturated_pixels"]
        #: The number of lens systems injected.
        self.lens_count = counts["lenses"]
        self._truth = raw.truth

    @property
    def truth(self):
        """The truth list (FIELD.truth.txt) as an astropy Table: ID, X_IMAGE, Y_IMAGE (1-based
        pixels), ALPHA_J2000, DELTA_J2000 (deg), KIND (1 lens galaxy, 2 lensed image, 3 galaxy,
        4 star), MAG, THETA_E (arcsec; lenses and their images), SYSTEM (1..lenses, else 0);
        lens systems first, at full precision."""
        from astropy.table import Table
        units = {"X_IMAGE": "pix", "Y_IMAGE": "pix", "ALPHA_J2000": "deg",
                 "DELTA_J2000": "deg", "MAG": "mag", "THETA_E": "arcsec"}
        table = Table()
        for name, values in self._truth.items():
            table[name] = values
            table[name].unit = _unit(units.get(name, ""))
        return table


def simulate_field(size=4096, *, seed=1, lenses=0, pixel_scale=None, seeing=None, gain=None,
                   noise_sigma=None, limiting_mag=None, mag_zero=None, saturate=None,
                   min_einstein_radius=0.0, max_einstein_radius=0.0, ra=150.0, dec=2.0,
                   config=None, database=None, population=None, threads=0):
    """Simulates a survey field with `lenses` injected galaxy-galaxy lenses, as `octarc
    simulate field` does: field galaxies and stars, Poisson sky noise, a TAN WCS.

    size          the image side, pixels.
    seed          the master seed (an integer >= 0): the result depends on it alone.
    pixel_scale, seeing, gain, mag_zero, saturate
                  arcsec/pixel, PSF FWHM (arcsec), e-/ADU, magnitude zero point, saturation
                  (ADU); None: from `config`, else 0.257, 0.9, 54, 30, 30000 (the DLS R band).
    noise_sigma   the sky noise per pixel, ADU; or `limiting_mag`, the 5-sigma limiting
                  magnitude in a 2 x FWHM aperture (default 26); not both.
    min_einstein_radius, max_einstein_radius
                  redraw lens systems outside these Einstein radii, arcsec (0: no limit).
    ra, dec       the field centre, deg.
    config        an octarc .sex file: PIXEL_SCALE, SEEING_FWHM, GAIN, MAG_ZEROPOINT,
                  SATUR_LEVEL.
    database      a RealGalaxyCatalog of lensed source galaxies (None: synthetic).
    population    a lens population file (None: the dls preset).
    threads       worker threads (0: every core).

    Returns a SimulatedField. ValueError with octarc's one-line message for a bad value;
    OSError for a file that cannot be read. Ctrl-C interrupts the call."""
    def number(value):
        return None if value is None else float(value)

    raw = _python_names(
        _octarc._simulate_field,
        _natural(size, "size"), number(pixel_scale), number(seeing), number(gain),
        number(noise_sigma),
        number(limiting_mag), number(mag_zero), number(saturate), _natural(lenses, "lenses"),
        float(min_einstein_radius), float(max_einstein_radius), _natural(seed, "seed", 2 ** 64 - 1),
        float(ra), float(dec), None if config is None else os.fspath(config),
        "" if database is None else os.fspath(database),
        "" if population is None else os.fspath(population), _natural(threads, "threads"))
    _warn(raw.warnings)
    return SimulatedField(raw)


def inject_lenses(image, *, lenses, pixel_scale, seeing, mag_zero, gain, weight=None,
                  header=None, seed=1, min_einstein_radius=0.0, max_einstein_radius=0.0,
                  database=None, population=None, threads=0):
    """Injects `lenses` simulated galaxy-galaxy lenses into a real image, as `octarc demo
    --into IMAGE` does: the systems of `simulate_field` (the same draws and rendering, at least
    30" apart and away from the edges), convolved with a Gaussian PSF of `seeing`, with the
    photon noise of their own light, added to the image's pixels as they are (sky and all).

    image         2-D image (read as by `detect`; never modified).
    lenses        the number of lens systems.
    pixel_scale, seeing, mag_zero, gain
                  the image's arcsec/pixel, PSF FWHM (arcsec), magnitude zero point and
                  e-/ADU (all needed, as `octarc demo --into` needs them).
    weight        its weight map (a 2-D array of the image's shape), returned unchanged as
                  float32.
    header        its astropy Header or WCS (or a header's text): the truth list's RA and
                  Dec (NaN without a celestial WCS); the result's header, with NLENSES and
                  SIMSEED added.
    seed, min_einstein_radius, max_einstein_radius, database, population, threads
                  as for `simulate_field`.

    Returns a SimulatedField: `image` the image with the lenses (float32), `weight` the weight
    map (None without one), `header`, and `truth` the lens systems only (`sky_sigma` is 0:
    the image's own noise is not estimated). ValueError with octarc's one-line message for a
    bad value or an array of the wrong shape or type."""
    array, _ = _image_array(image, "image")
    raw = _python_names(
        _octarc._inject_lenses,
        array, None if weight is None else _image_array(weight, "weight")[0],
        _header_cards(header), _natural(lenses, "lenses"), float(pixel_scale), float(seeing),
        float(mag_zero), float(gain), float(min_einstein_radius), float(max_einstein_radius),
        _natural(seed, "seed", 2 ** 64 - 1), "" if database is None else os.fspath(database),
        "" if population is None else os.fspath(population), _natural(threads, "threads"))
    return SimulatedField(raw)


# The selection and search stages, which use the helpers above.
from ._selection import Grid, Model  # noqa: E402
from ._search import SearchResult, search  # noqa: E402
