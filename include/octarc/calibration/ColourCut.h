// The calibration of the search's colour cut (COLOUR_CUT B,MAX) on a simulation made in two
// bands (simulate lenses --band B): the fraction of the simulated arcs that the cut keeps, as a
// function of MAX (its completeness), and the MAX that keeps a given fraction.
//
// The search removes a candidate when ARC_COLOUR_B - LENS_COLOUR_B > MAX and keeps it when
// either colour is NaN (no lens detected apart from the arc, or no positive flux in a band), so
// the simulated arcs without both colours count as kept at every MAX, as they would be kept in
// the search.
//
// Weighted (calibration/Weights.h): each arc counts its SIM_WEIGHT; the fractions carry their
// Clopper-Pearson 68.27 % intervals (n the Kish effective number of the arcs).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "octarc/calibration/Weights.h"
#include "octarc/core/Table.h"

namespace octarc {

struct ColourCutSettings {
  // The MAX values tabulated: maxLoMag, maxLoMag + stepMag, ... up to maxHiMag.
  double maxLoMag = -1.0, maxHiMag = 3.0, stepMag = 0.05;
  // Completeness levels for which the smallest MAX is reported.
  std::vector<double> completenessLevels = {0.90, 0.95, 0.99};
};

struct ColourCutRow {
  double maxMag = 0.0;
  std::int64_t kept = 0;    // arcs kept by COLOUR_CUT B,maxMag
  double keptWeight = 0.0;  // their SIM_WEIGHT sum
  FractionInterval fraction;
};

struct ColourCutLevel {
  double completeness = 0.0;
  // The smallest MAX keeping at least that (weighted) fraction of the arcs: one of the arcs' own
  // colour differences; -inf when the arcs without both colours alone reach it (any MAX does).
  double maxMag = 0.0;
};

struct ColourCutStudy {
  std::string band;
  std::string arcSelection;               // the expression that picked the arcs (systems table)
  WeightedCount arcs;                     // the normalisation
  std::int64_t withColours = 0;           // of them with both colours finite
  std::vector<double> differences;        // ARC_COLOUR_B - LENS_COLOUR_B of those, sorted
  std::vector<double> differenceWeights;  // their SIM_WEIGHT, in the same order
  std::vector<ColourCutRow> rows;
  std::vector<ColourCutLevel> levels;
};

// The column names of band `band` the study reads.
std::string arcColourColumn(const std::string& band);   // ARC_COLOUR_<band>
std::string lensColourColumn(const std::string& band);  // LENS_COLOUR_<band>

// The study on the rows of `systems` that pass `arcSelection` (a ColumnExpression; NaN or 0
// leaves a row out), each weighted by its SIM_WEIGHT (1 without the column). ConfigError naming the
// column when the table lacks the band's colours, for an expression that does not parse, or for a
// bad MAX range (COLOUR_CUT_MAX).
ColourCutStudy colourCutStudy(const Table& systems, const std::string& band,
                              const std::string& arcSelection, const ColourCutSettings& settings);

// ConfigError naming COLOUR_CUT_MAX for a range that is empty, reversed, not finite, or of more
// than 10000 steps.
void checkColourCutSettings(const ColourCutSettings& settings);

}  // namespace octarc
