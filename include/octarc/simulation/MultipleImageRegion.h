// The source-plane region of the elliptical potential (LensModel.h) where a source has more
// than one image, so that a simulated system is strongly lensed by construction.
//
// Without a core the potential is isothermal, psi = b r F(phi), and along each image-plane
// direction phi the lens equation is linear in r: beta = r u(phi) - alpha(phi), with alpha
// depending on phi only. Two curves bound the region:
//   - the cut (pseudo-caustic), the image of the lens centre, beta = -alpha(phi): inside it a
//     source has at least two images;
//   - the tangential caustic, the image of the critical curve r_t(phi) = trace(Hessian at r = 1)
//     (det Hessian = 0 for isothermal potentials, so det A = 1 - r_t / r): inside it, two more.
// The region is the union of the two insides (a caustic poking out of the cut, a naked cusp,
// gives three images there). A core theta_c > 0 shrinks the region a little near the cut; the
// simulations use theta_c = 0, for which it is exact up to the polygons' sampling.
#pragma once

#include <random>
#include <vector>

#include "octarc/simulation/LensModel.h"

namespace octarc::simulation {

class MultipleImageRegion {
 public:
  // Both curves as polygons of `vertices` points, evenly spaced in the image-plane direction.
  // Throws ConfigError as EllipticalPotentialLens does, or for fewer than 16 vertices.
  explicit MultipleImageRegion(const EllipticalPotentialParams& params, int vertices = 2048);

  // True inside the cut or inside the tangential caustic (arcsec, sky axes, about the lens).
  bool contains(const Vec2& betaArcsec) const;
  // The radius of a circle about the lens that holds both curves.
  double boundingRadiusArcsec() const { return boundingRadiusArcsec_; }
  const std::vector<Vec2>& cut() const { return cut_; }
  const std::vector<Vec2>& tangentialCaustic() const { return caustic_; }

  // A point uniform in area inside the region: uniform in the bounding disc, drawn again until
  // inside (the region fills about (1 - eps) of the disc, so few draws are needed).
  Vec2 drawUniform(std::mt19937_64& rng) const;

 private:
  std::vector<Vec2> cut_;
  std::vector<Vec2> caustic_;
  double boundingRadiusArcsec_ = 0.0;
};

}  // namespace octarc::simulation
