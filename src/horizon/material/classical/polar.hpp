#pragma once
// Polar decomposition F = R U (R proper orthogonal, U symmetric positive definite) and
// the logarithmic (Hencky) strain ln U, from the singular value decomposition
// F = W S V^T: R = W V^T, U = V S V^T, ln U = V ln(S) V^T (e.g. Bonet and Wood 2008,
// "Nonlinear Continuum Mechanics for Finite Element Analysis", 2nd ed., sec. 3.5; the
// SVD route is the one of Higham 1986, "Computing the polar decomposition", SIAM J. Sci.
// Stat. Comput. 7, eq. 1.2). Eigen's JacobiSVD of a 3 x 3 matrix is accurate to round-off
// for any conditioning, so no iteration count or tolerance is involved.
#include <Eigen/Dense>
#include <cmath>

namespace horizon::classical {

using Mat3 = Eigen::Matrix3d;

struct Polar {
  Mat3 R = Mat3::Identity();
  Mat3 U = Mat3::Identity();
  Mat3 log_U = Mat3::Zero();  // Hencky strain in the unrotated frame
  bool ok = false;            // false when det F <= 0 (an inverted or flattened particle)
};

inline Polar polar_decomposition(const Mat3& F) {
  Polar p;
  const double J = F.determinant();
  if (!(J > 0) || !std::isfinite(J)) return p;
  const Eigen::JacobiSVD<Mat3> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Mat3& W = svd.matrixU();
  const Mat3& V = svd.matrixV();
  Eigen::Vector3d s = svd.singularValues();
  // det F = det(W) det(S) det(V) > 0 with every singular value >= 0: det(W) det(V) = +1,
  // so R = W V^T is a proper rotation even when the SVD put reflections in W and V.
  if (!(s.minCoeff() > 0)) return p;
  p.R = W * V.transpose();
  p.U = V * s.asDiagonal() * V.transpose();
  const Eigen::Vector3d ls(std::log(s[0]), std::log(s[1]), std::log(s[2]));
  p.log_U = V * ls.asDiagonal() * V.transpose();
  p.ok = true;
  return p;
}

}  // namespace horizon::classical
