#include "octarc/simulation/Population.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>

#include "octarc/core/DataFiles.h"
#include "octarc/core/Error.h"
#include "octarc/core/Format.h"

namespace octarc::simulation {

namespace {

constexpr int kMaxRedshiftDraws = 1000;
constexpr double kMaxRedshift = 20.0;

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

}  // namespace

double MagnitudePowerLaw::sample(std::mt19937_64& rng) const {
  const double u = std::uniform_real_distribution<double>(0.0, 1.0)(rng);
  const double k = slopePerMag * std::log(10.0);
  if (std::abs(k * (magMax - magMin)) < 1e-12) return magMin + u * (magMax - magMin);
  // Inverse of the CDF of a density proportional to exp(k m) on [magMin, magMax].
  return magMin + std::log1p(u * std::expm1(k * (magMax - magMin))) / k;
}

double MagnitudeSizeRelation::sample(double mag, std::mt19937_64& rng) const {
  const double scatter =
      scatterDex > 0.0 ? std::normal_distribution<double>(0.0, scatterDex)(rng) : 0.0;
  return halfLightArcsecAtRef * std::pow(10.0, log10SlopePerMag * (mag - magRef) + scatter);
}

std::optional<double> MagnitudeRedshiftRelation::sample(double mag, double zFloor, double zMin,
                                                        double zMax, std::mt19937_64& rng) const {
  const double lo = std::max(zMin, zFloor);
  if (lo > zMax) return std::nullopt;
  const double median = zAtRef + slopePerMag * (mag - magRef);
  std::normal_distribution<double> scatterDist(0.0, scatter > 0.0 ? scatter : 1.0);
  for (int i = 0; i < kMaxRedshiftDraws; ++i) {
    const double z = median + (scatter > 0.0 ? scatterDist(rng) : 0.0);
    if (z >= lo && z <= zMax) return z;
    if (!(scatter > 0.0)) break;
  }
  return std::nullopt;
}

double LinearTable::operator()(double xValue) const {
  if (x.empty()) return 0.0;
  if (xValue <= x.front()) return y.front();
  if (xValue >= x.back()) return y.back();
  const auto it = std::upper_bound(x.begin(), x.end(), xValue);
  const auto i = static_cast<std::size_t>(it - x.begin());
  const double t = (xValue - x[i - 1]) / (x[i] - x[i - 1]);
  return y[i - 1] + t * (y[i] - y[i - 1]);
}

double VelocityDispersionFunction::density(double sigmaKmPerS) const {
  if (!(sigmaKmPerS > 0.0)) return 0.0;
  const double x = sigmaKmPerS / sigmaStarKmPerS;
  return phiStarH3PerMpc3 * std::pow(x, alpha) * std::exp(-std::pow(x, beta)) * beta /
         std::tgamma(alpha / beta) / sigmaKmPerS;
}

std::optional<double> VelocityDispersionFunction::sampleWeighted(double power, double lo, double hi,
                                                                 int maxDraws,
                                                                 std::mt19937_64& rng) const {
  // phi(sigma) sigma^p dsigma is proportional to x^((alpha + p)/beta - 1) e^-x dx for
  // x = (sigma/sigma*)^beta.
  std::gamma_distribution<double> gamma((alpha + power) / beta, 1.0);
  for (int i = 0; i < maxDraws; ++i) {
    const double sigma = sigmaStarKmPerS * std::pow(gamma(rng), 1.0 / beta);
    if (sigma > lo && sigma < hi) return sigma;
  }
  return std::nullopt;
}

ComovingVolumeRedshifts::ComovingVolumeRedshifts(const FlatLambdaCdm& cosmology, double zMin,
                                                 double zMax, int nodes)
    : cosmology_(cosmology.params()) {
  z_.resize(std::size_t(nodes));
  cdf_.assign(std::size_t(nodes), 0.0);
  double previous = 0.0;
  for (int i = 0; i < nodes; ++i) {
    z_[std::size_t(i)] = zMin + (zMax - zMin) * i / (nodes - 1);
    const double v = cosmology.comovingVolumePerRedshiftMpc3PerSr(z_[std::size_t(i)]);
    if (i > 0)  // trapezoids
      cdf_[std::size_t(i)] = cdf_[std::size_t(i - 1)] +
                             0.5 * (v + previous) * (z_[std::size_t(i)] - z_[std::size_t(i - 1)]);
    previous = v;
  }
  for (double& c : cdf_) c /= cdf_.back();
}

double ComovingVolumeRedshifts::sample(std::mt19937_64& rng) const {
  const double u = std::uniform_real_distribution<double>(0.0, 1.0)(rng);
  const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), u);
  if (it == cdf_.begin()) return z_.front();
  if (it == cdf_.end()) return z_.back();
  const auto i = std::size_t(it - cdf_.begin());
  const double t = (u - cdf_[i - 1]) / (cdf_[i] - cdf_[i - 1]);
  return z_[i - 1] + t * (z_[i] - z_[i - 1]);
}

void PopulationModel::tabulate(const FlatLambdaCdm& cosmology) {
  lensRedshifts = ComovingVolumeRedshifts(cosmology, lensZMin, lensZMax);
}

std::optional<LensDraw> PopulationModel::drawLens(const FlatLambdaCdm& cosmology,
                                                  std::mt19937_64& rng) const {
  const std::optional<double> sigma =
      lensVdf.sampleWeighted(4.0, sigmaMinKmPerS, sigmaMaxKmPerS, maxLensAttempts, rng);
  if (!sigma)
    throw ConfigError(sourcePath + ": lens.sigma_min_km_s/lens.sigma_max_km_s: no lens with " +
                      formatNumber(sigmaMinKmPerS) + " < sigma_v < " +
                      formatNumber(sigmaMaxKmPerS) +
                      " km/s from the velocity dispersion function in " +
                      std::to_string(maxLensAttempts) + " draws");
  LensDraw d;
  d.sigmaKmPerS = *sigma;
  const CosmologyParams& p = cosmology.params();
  const CosmologyParams& t = lensRedshifts.cosmology();
  const bool tabulated = !lensRedshifts.empty() && p.h0KmPerSPerMpc == t.h0KmPerSPerMpc &&
                         p.omegaMatter == t.omegaMatter && p.omegaLambda == t.omegaLambda;
  d.redshift = tabulated ? lensRedshifts.sample(rng)
                         : ComovingVolumeRedshifts(cosmology, lensZMin, lensZMax).sample(rng);
  const double scatter =
      fjScatterMag > 0.0 ? std::normal_distribution<double>(0.0, fjScatterMag)(rng) : 0.0;
  d.absoluteMag = fjAbsMagStar - 10.0 * std::log10(d.sigmaKmPerS / fjSigmaStarKmPerS) + scatter;
  d.mag = d.absoluteMag + cosmology.distanceModulusMag(d.redshift) + lensKCorrectionMag(d.redshift);
  if (!(d.mag >= lensMagMin && d.mag <= lensMagMax)) return std::nullopt;
  return d;
}

std::optional<SourceDraw> PopulationModel::drawSource(GalaxyType type, std::mt19937_64& rng) const {
  SourceDraw d;
  d.mag = sourceMagnitude.sample(rng);
  d.halfLightArcsec = sourceSize.sample(d.mag, rng);
  const auto it = sourceRedshift.find(type);
  if (it == sourceRedshift.end())
    throw ConfigError(sourcePath + ": no magnitude-redshift relation for type " +
                      galaxyTypeName(type));
  const std::optional<double> z = it->second.sample(d.mag, sourceZMin, sourceZMin, sourceZMax, rng);
  if (!z) return std::nullopt;
  d.redshift = *z;
  return d;
}

double PopulationModel::lensingWeight(double zLens, double zSource,
                                      const FlatLambdaCdm& cosmology) const {
  if (!(zSource >= zLens + sourceMinDzBehindLens) || !(zSource > zLens)) return 0.0;
  const double ratio = cosmology.angularDiameterDistanceMpc(zLens, zSource) /
                       cosmology.angularDiameterDistanceMpc(zSource);
  return ratio * ratio;
}

std::string defaultPopulationModelPath() {
  return dataFile("simulation/population.txt");
}

std::vector<std::string> populationPresetNames() {
  return {"physical", "dls"};
}

std::string populationPresetPath(const std::string& preset) {
  if (preset == "physical") return defaultPopulationModelPath();
  if (preset == "dls") return dataFile("simulation/population-dls.txt");
  throw ConfigError("population preset " + quoteForMessage(preset) +
                    " is not one of physical, dls");
}

namespace {

// The ranges and relations that the draws need, ConfigError naming the file and key otherwise.
void checkPopulationModel(const PopulationModel& m, double maxAttempts) {
  auto fail = [&m](const std::string& key, const std::string& what) {
    throw ConfigError(m.sourcePath + ": key " + key + ": " + what);
  };
  auto checkRange = [&](const std::string& prefix, const MagnitudePowerLaw& p) {
    if (!(p.magMin < p.magMax))
      fail(prefix + ".mag_min", "must be less than " + prefix + ".mag_max (" +
                                    formatNumber(p.magMin) + " >= " + formatNumber(p.magMax) + ")");
  };
  checkRange("source", m.sourceMagnitude);
  if (!(m.lensMagMin < m.lensMagMax))
    fail("lens.mag_min", "must be less than lens.mag_max (" + formatNumber(m.lensMagMin) +
                             " >= " + formatNumber(m.lensMagMax) + ")");
  const VelocityDispersionFunction& vdf = m.lensVdf;
  if (!(vdf.sigmaStarKmPerS > 0.0)) fail("lens.vdf.sigma_star_km_s", "must be positive");
  if (!(vdf.beta > 0.0)) fail("lens.vdf.beta", "must be positive");
  if (!(vdf.alpha > 0.0)) fail("lens.vdf.alpha", "must be positive");
  if (!(vdf.phiStarH3PerMpc3 > 0.0)) fail("lens.vdf.phi_star_h3_per_mpc3", "must be positive");
  if (m.skipEinsteinRadiusBelowArcsec < 0.0) fail("lens.skip_theta_e_below_arcsec", "must be >= 0");
  if (!(m.sourceSize.halfLightArcsecAtRef > 0.0))
    fail("source.size.r_half_arcsec_at_ref", "must be positive");
  if (m.sourceSize.scatterDex < 0.0) fail("source.size.scatter_dex", "must be >= 0");
  if (!(m.sourceZMin >= 0.0 && m.sourceZMin < m.sourceZMax))
    fail("source.z_min", "must be >= 0 and less than source.z_max");
  if (m.sourceMinDzBehindLens < 0.0) fail("source.min_dz_behind_lens", "must be >= 0");
  for (const auto& [type, rel] : m.sourceRedshift)
    if (rel.scatter < 0.0)
      fail(std::string("source.z.") + galaxyTypeName(type) + ".scatter", "must be >= 0");
  if (!(m.lensZMin > 0.0 && m.lensZMin < m.lensZMax))
    fail("lens.z_min", "must be > 0 and less than lens.z_max");
  // The distances are integrated up to these redshifts for every draw: keep them where the
  // cosmology is accurate (and the integration short).
  if (!(m.sourceZMax <= kMaxRedshift)) fail("source.z_max", "must be at most 20");
  if (!(m.lensZMax <= kMaxRedshift)) fail("lens.z_max", "must be at most 20");
  if (!(m.fjSigmaStarKmPerS > 0.0)) fail("lens.fj.sigma_star_km_s", "must be positive");
  if (m.fjScatterMag < 0.0) fail("lens.fj.scatter_mag", "must be >= 0");
  if (!(m.sigmaMinKmPerS > 0.0 && m.sigmaMinKmPerS < m.sigmaMaxKmPerS))
    fail("lens.sigma_min_km_s", "must be positive and less than lens.sigma_max_km_s (" +
                                    formatNumber(m.sigmaMinKmPerS) +
                                    " >= " + formatNumber(m.sigmaMaxKmPerS) + ")");
  if (!(maxAttempts >= 1.0 && maxAttempts <= 1e9 && maxAttempts == std::floor(maxAttempts)))
    fail("lens.max_attempts", "must be a whole number between 1 and 1e9");
  const LinearTable& k = m.lensKCorrectionMag;
  if (k.x.size() != k.y.size())
    fail("lens.kcorr.mag", "has " + std::to_string(k.y.size()) + " values but lens.kcorr.z has " +
                               std::to_string(k.x.size()));
  for (std::size_t i = 1; i < k.x.size(); ++i)
    if (!(k.x[i] > k.x[i - 1])) fail("lens.kcorr.z", "must be strictly increasing");
}

}  // namespace

PopulationModel readPopulationModel(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw IoError(path + ": cannot open population parameter file");
  PopulationModel m;
  m.sourcePath = path;
  m.sourceRedshift[GalaxyType::Elliptical] = {};
  m.sourceRedshift[GalaxyType::Spiral] = {};
  m.sourceRedshift[GalaxyType::Irregular] = {};

  // Every key and where its value goes.
  std::map<std::string, std::function<void(const std::vector<double>&)>> setters;
  auto scalar = [&setters](const std::string& key, double* target) {
    setters[key] = [target](const std::vector<double>& v) { *target = v.front(); };
  };
  scalar("source.mag_min", &m.sourceMagnitude.magMin);
  scalar("source.mag_max", &m.sourceMagnitude.magMax);
  scalar("source.mag_slope", &m.sourceMagnitude.slopePerMag);
  scalar("source.size.mag_ref", &m.sourceSize.magRef);
  scalar("source.size.r_half_arcsec_at_ref", &m.sourceSize.halfLightArcsecAtRef);
  scalar("source.size.log10_slope_per_mag", &m.sourceSize.log10SlopePerMag);
  scalar("source.size.scatter_dex", &m.sourceSize.scatterDex);
  scalar("source.z_min", &m.sourceZMin);
  scalar("source.z_max", &m.sourceZMax);
  scalar("source.min_dz_behind_lens", &m.sourceMinDzBehindLens);
  for (auto& [type, rel] : m.sourceRedshift) {
    const std::string p = std::string("source.z.") + galaxyTypeName(type) + ".";
    scalar(p + "mag_ref", &rel.magRef);
    scalar(p + "z_at_ref", &rel.zAtRef);
    scalar(p + "slope_per_mag", &rel.slopePerMag);
    scalar(p + "scatter", &rel.scatter);
  }
  scalar("lens.vdf.phi_star_h3_per_mpc3", &m.lensVdf.phiStarH3PerMpc3);
  scalar("lens.vdf.sigma_star_km_s", &m.lensVdf.sigmaStarKmPerS);
  scalar("lens.vdf.alpha", &m.lensVdf.alpha);
  scalar("lens.vdf.beta", &m.lensVdf.beta);
  scalar("lens.mag_min", &m.lensMagMin);
  scalar("lens.mag_max", &m.lensMagMax);
  scalar("lens.skip_theta_e_below_arcsec", &m.skipEinsteinRadiusBelowArcsec);
  scalar("lens.z_min", &m.lensZMin);
  scalar("lens.z_max", &m.lensZMax);
  scalar("lens.fj.abs_mag_star", &m.fjAbsMagStar);
  scalar("lens.fj.sigma_star_km_s", &m.fjSigmaStarKmPerS);
  scalar("lens.fj.scatter_mag", &m.fjScatterMag);
  scalar("lens.sigma_min_km_s", &m.sigmaMinKmPerS);
  scalar("lens.sigma_max_km_s", &m.sigmaMaxKmPerS);
  double maxAttempts = 0.0;
  scalar("lens.max_attempts", &maxAttempts);
  const std::set<std::string> listKeys = {"lens.kcorr.z", "lens.kcorr.mag"};
  setters["lens.kcorr.z"] = [&m](const std::vector<double>& v) { m.lensKCorrectionMag.x = v; };
  setters["lens.kcorr.mag"] = [&m](const std::vector<double>& v) { m.lensKCorrectionMag.y = v; };

  std::set<std::string> seen;
  std::string line;
  int lineNo = 0;
  while (std::getline(in, line)) {
    ++lineNo;
    const std::string where = path + ": line " + std::to_string(lineNo);
    if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    line = trim(line);
    if (line.empty()) continue;
    const auto eq = line.find('=');
    if (eq == std::string::npos) throw ConfigError(where + ": expected 'key = value'");
    const std::string key = trim(line.substr(0, eq));
    const auto setter = setters.find(key);
    if (setter == setters.end()) throw ConfigError(where + ": unknown key " + quoteForMessage(key));
    if (!seen.insert(key).second) throw ConfigError(where + ": key " + key + " given twice");
    std::istringstream values(line.substr(eq + 1));
    std::vector<double> numbers;
    std::string token;
    while (values >> token) {
      std::size_t used = 0;
      double v = 0.0;
      try {
        v = std::stod(token, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != token.size() || !std::isfinite(v))
        throw ConfigError(where + ": key " + key + ": " + quoteForMessage(token) +
                          " is not a finite number");
      numbers.push_back(v);
    }
    if (numbers.empty()) throw ConfigError(where + ": key " + key + " has no value");
    if (numbers.size() > 1 && !listKeys.count(key))
      throw ConfigError(where + ": key " + key + " takes one number");
    setter->second(numbers);
  }
  for (const auto& [key, setter] : setters)
    if (!seen.count(key)) throw ConfigError(path + ": missing key " + key);

  checkPopulationModel(m, maxAttempts);
  m.maxLensAttempts = static_cast<int>(maxAttempts);
  m.name = std::filesystem::path(path).stem().string();
  m.tabulate(FlatLambdaCdm());
  return m;
}

}  // namespace octarc::simulation
