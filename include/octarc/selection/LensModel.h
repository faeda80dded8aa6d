// The learned selection's model as a saved artefact (SELECTION_METHOD TREES): which features a
// row is described by, the trees (selection/TreeModel.h), how they were trained, and the survey
// setup they were trained for. Like the grid file, a FITS file reusable by every search on the
// same setup.
//
// Features, per catalog row (lensFeatureNames(), in order): ARCNESS, ANTIARCNESS, E_IMAGE,
// log10(SNR_ISO), the size sqrt(2) SIZE_IMAGE in arcsec, THRESH_LEVEL, and the context columns
// of selection/ArcContext.h. Simulated arcs carry the context columns (simulate lenses writes
// them); a survey catalog's are computed from its rows.
//
// The score. The trees give the log-odds of "lens arc" for the training mix, in which the arcs
// weigh ARCWEIGH and the other rows OTHWEIGH. LENS_SCORE is the probability once those odds are
// moved to the survey's own: log-odds + ln(prior / (1 - prior)) - ln(ARCWEIGH / OTHWEIGH), with
// prior = the expected fraction of lens-arc rows among the rows scored (searchPriorFraction).
// It reads as the expected fraction of lens arcs among rows of that score, for a survey of the
// model's setup holding the lens density assumed.
//
// File layout: an empty primary HDU and one BINTABLE, LENS_MODEL. Header: OCTMODEL (format 1),
// METHOD ("TREES"), NFEAT and FEATn (the features), CTXRAD (the context's reach, arcsec), the
// training (NARC simulated arc rows, every level, ARCWEIGH their weight, NEFFARC their Kish
// effective number, NOTHER other rows, OTHWEIGH their weight, SNRMIN and RESMIN the rows' S/N
// floor and resolved size in arcsec, ROUNDS, DEPTH, ETA, SUBSAMPL, TRSEED), ARCROWS (the mean
// number of such arc rows per simulated arc system, ARC_FOUND = 1, weighted) and the survey
// setup (SurveySetup.h), MODELLEN
// (characters of the model). One column MODEL of 1000-character strings: XGBoost's JSON model,
// cut in order (the last string shorter).
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "octarc/core/Table.h"
#include "octarc/selection/ArcContext.h"
#include "octarc/selection/SurveySetup.h"
#include "octarc/selection/TreeModel.h"

namespace octarc {

const std::vector<std::string>& lensFeatureNames();

// The features of `rows` of `table`, which holds the octopole columns and either the context
// columns or, when `contexts` is given (one per table row), not. ConfigError naming a missing
// column.
FeatureRows lensFeatures(const Table& table, const std::vector<std::int64_t>& rows,
                         double pixelScaleArcsec, const std::vector<ArcContext>* contexts);

struct LensModelTraining {
  std::int64_t arcRows = 0;
  double arcWeight = 0.0;
  double effectiveArcs = 0.0;
  std::int64_t otherRows = 0;
  double otherWeight = 0.0;
  double snrMin = 0.0;
  double resolvedMinArcsec = 0.0;
  double arcRowsPerSystem = 1.0;  // mean arc rows trained on per arc system (weighted)
  TreeTraining trees;
};

struct SavedLensModel {
  TreeModel trees;
  std::vector<std::string> features;  // lensFeatureNames() when made by this version
  double contextRadiusArcsec = 6.0;
  LensModelTraining training;
  SurveySetup setup;
};

// Writes the model file at `path` itself (give the temporary path of an AtomicFile /
// OutputFiles entry). IoError naming the file when it cannot be written.
void saveLensModel(const std::string& path, const SavedLensModel& model);

// Reads a model file. IoError naming the file and what is wrong when it is not one (no
// LENS_MODEL table, a missing keyword, features this version does not compute, a model that
// does not load).
SavedLensModel loadLensModel(const std::string& path);

// The log-odds shift from the training mix to a survey whose rows hold lens arcs at
// `priorFraction` (0 < priorFraction < 1).
double priorLogOddsShift(const LensModelTraining& training, double priorFraction);

// The expected fraction of lens-arc rows among `rowsScored` rows over `areaDeg2`, for
// `lensesPerDeg2` arc systems per square degree, each seen in `arcRowsPerSystem` rows; clamped
// into [1e-12, 0.5].
double searchPriorFraction(double lensesPerDeg2, double areaDeg2, std::int64_t rowsScored,
                           double arcRowsPerSystem);

// The probability from log-odds.
inline double logistic(double logOdds) {
  return logOdds >= 0 ? 1.0 / (1.0 + std::exp(-logOdds))
                      : std::exp(logOdds) / (1.0 + std::exp(logOdds));
}

}  // namespace octarc
