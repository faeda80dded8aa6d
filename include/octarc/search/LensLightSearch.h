// The lens-light part of a search (LENS_LIGHT, METHOD.md section 5), between detection and
// selection:
//
//   the run's catalog --> bright smooth galaxies fitted and subtracted (lenslight/)
//     --> the residual image detected and measured again, at the run's levels and columns
//     --> LOCAL: the residual's rows near a fitted galaxy appended to the catalog (renumbered
//         past the run's NUMBERs, their footprints added), each with that galaxy as its lens
//     --> IMAGE: the residual's catalog replaces the run's, plus each fitted galaxy's own
//         level-1 row (renumbered, with its footprint), kept as a lens and never selected
//
// SearchRun::lensLightOf then tells the selection (search/Search.h) which rows came from the
// residual and which galaxy is their lens.
#pragma once

#include <functional>

#include "octarc/run/CatalogAssembly.h"
#include "octarc/run/DetectionRun.h"
#include "octarc/search/SearchRun.h"

namespace octarc {

// Applies settings.lensLight to `run` (its catalog, footprints, levels and prepared image, as
// detected here), filling run.lensLight and run.lensLightOf. With `fitBand` (LENS_LIGHT_BAND:
// that colour band's prepared image, settings.lensLightBand), the galaxies are fitted in it and
// their models scaled and PSF-matched to the searched image (lenslight::FitBandImage).
// ConfigError for a bad LENS_SELECT. `checkpoint`, when given, is called between the galaxies'
// fits and during the residual's detection (DetectionRequest::checkpoint).
void applyLensLight(SearchRun& run, const SearchRunSettings& settings, const ColumnPlan& columns,
                    const RunLog& log, const PreparedImage* fitBand = nullptr,
                    const std::function<void()>& checkpoint = {});

// The FITS table of the chosen galaxies (EXTNAME LENSFIT), one row each, in catalog order:
// NUMBER of the galaxy's level-1 row in the image's detection, LENS_NUMBER (the candidates'
// LENS_NUMBER of it, SearchRun::lensNumbers), X_IMAGE/Y_IMAGE (catalog), the fitted centre, flux,
// half-light radius, index, axis ratio and angle with their errors, chi^2 per degree of
// freedom, the solver's iterations, the pre-screen's QUICK_SNR, BAND_RATIO (LENS_LIGHT_BAND: the
// searched image's flux over that band's in the galaxy's core; NaN without) and LENSFIT_FLAGS
// (lenslight::FitFailure bits: 0, 8, 32 or 40 subtracted, 8 an index or axis ratio at its bound,
// 16 not fitted by the pre-screen, 32 fitted in LENS_LIGHT_BAND, 64 no flux ratio; the
// parameters of a galaxy not fitted are its start; with 32, the flux is the searched image's and
// the other parameters and chi^2 are the band's fit's).
FitsTable lensFitTable(const SearchRun& run);

}  // namespace octarc
