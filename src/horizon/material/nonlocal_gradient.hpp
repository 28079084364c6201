#pragma once
// The shape tensor and the nonlocal deformation gradient of one particle (Silling et al.
// 2007, seed 003 eq. 17 and 134; discrete form of digest sec. 9):
//   K_i = sum_j omega_ij V_j xi_ij (x) xi_ij,   F_i = (sum_j omega_ij V_j Y_ij (x) xi_ij) K_i^-1
// over the bonds that act. F_i equals F exactly for any homogeneous deformation
// Y = F xi (digest sec. 13 check 4), whatever the family looks like. Shared by the
// correspondence model (material/models/correspondence.hpp) and the output stress field
// (material/stress_field.hpp).
//
// In d < 3 dimensions only the first d axes are used: K_i is d x d (it is singular out
// of plane), K_i^-1 is returned in the top-left d x d block of a 3 x 3 matrix with zeros
// elsewhere, and F_i gets 1 on the unused diagonal entries (the plane-stress thickness
// stretch is the stress law's business).
//
// A shape tensor that is singular or ill-conditioned (fewer than d intact bonds that
// span the d axes, e.g. after damage) is refused: its smallest eigenvalue must exceed
// `tolerance` times its largest. The particle then carries no stress and interacts by
// contact only (seed 000 digest sec. 6.1: "treat such a particle as fully failed").
#include <Eigen/Dense>
#include <cmath>

#include "horizon/core/vec3.hpp"
#include "horizon/kernels/affine.hpp"

namespace horizon {

class NonlocalGradient {
 public:
  using Mat3 = Eigen::Matrix3d;

  // One acting bond: reference bond xi, deformed bond Y, weight omega V_j.
  void add(const Vec3& xi, const Vec3& Y, double wv) {
    const Eigen::Vector3d a(xi.x, xi.y, xi.z), y(Y.x, Y.y, Y.z);
    K_.noalias() += wv * a * a.transpose();
    N_.noalias() += wv * y * a.transpose();
  }

  // The sums of add() gathered elsewhere (the affine force pass sums them in its breaking
  // sweep: kernels/affine.hpp gradient_add), K and N row-major.
  void set_sums(const double* K, const double* N) {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) K_(r, c) = K[3 * r + c], N_(r, c) = N[3 * r + c];
  }

  const Mat3& shape_tensor() const { return K_; }

  // The reciprocal condition number of the d x d shape tensor (smallest over largest
  // eigenvalue; 0 when empty): kernels/affine.hpp shape_condition, closed form.
  double reciprocal_condition(int d) const {
    double k[9];
    rows(K_, k);
    return kernels::shape_condition(k, d);
  }

  // K^-1 and F as described above; false (Kinv = 0, F = I) when the shape tensor is
  // refused. The device-portable kernel (kernels/affine.hpp gradient_finish) with the
  // operations of Eigen's inverse and product, so the bits Eigen gave.
  bool finish(int d, double tolerance, Mat3& Kinv, Mat3& F) const {
    double k[9], n[9], ki[9], f[9];
    rows(K_, k);
    rows(N_, n);
    const bool ok = kernels::gradient_finish(k, n, d, tolerance, ki, f);
    for (int c = 0; c < 9; ++c) Kinv(c / 3, c % 3) = ki[c], F(c / 3, c % 3) = f[c];
    return ok;
  }

 private:
  static void rows(const Mat3& m, double* a) {
    for (int c = 0; c < 9; ++c) a[c] = m(c / 3, c % 3);
  }

  Mat3 K_ = Mat3::Zero();
  Mat3 N_ = Mat3::Zero();
};

}  // namespace horizon
