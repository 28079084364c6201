#pragma once
// A rigid projectile (seed 002 digest sec. 9.2, 9.3): a sphere or an ogive-nosed cylinder of
// given mass and initial velocity, free to translate (3 degrees of freedom: no rotation,
// no spin), pushed by the particles it penetrates through the penalty contact of
// contact/rigid_contact.hpp and pushing them back with the opposite force. The explicit
// loop integrates it with the particles' velocity Verlet on the same step
// (solver/explicit.cpp):
//     v(n+1/2) = v(n) + dt/2 F(n)/M;  x(n+1) = x(n) + dt v(n+1/2);
//     contact at x(n+1) -> F(n+1);    v(n+1) = v(n+1/2) + dt/2 F(n+1)/M.
// F = -sum_i b_i V_i exactly, so body plus particles conserve momentum to round-off.
// Damping (solver.damping) does not act on the body.
#include <array>

#include "horizon/contact/rigid_contact.hpp"
#include "horizon/core/state_archive.hpp"
#include "horizon/deck/config.hpp"

namespace horizon {

struct System;

// Second-order Butterworth low-pass by the bilinear transform with the cutoff pre-warped
// (Oppenheim and Schafer, Discrete-Time Signal Processing, 3rd ed., sec. 7.1.2 and
// example 7.4): the analogue prototype H(s) = wc^2 / (s^2 + sqrt(2) wc s + wc^2) with
// s = (2/T)(1 - z^-1)/(1 + z^-1) and wc = (2/T) tan(pi fc T) gives, with K = tan(pi fc T),
//     b0 = K^2/(1 + sqrt(2) K + K^2),  b1 = 2 b0,  b2 = b0,
//     a1 = 2 (K^2 - 1)/(1 + sqrt(2) K + K^2),  a2 = (1 - sqrt(2) K + K^2)/(1 + sqrt(2) K + K^2),
//     y(n) = b0 x(n) + b1 x(n-1) + b2 x(n-2) - a1 y(n-1) - a2 y(n-2).
// Its gain is 1 at DC and exactly 1/sqrt(2) at fc; |H(f)|^2 = 1/(1 + (tan(pi f T)/K)^4).
// The first sample primes the memory (no start-up transient for a constant input).
struct Butterworth2 {
  double cutoff = 0;  // [Hz]; 0: pass-through
  double T = 0;       // the step the coefficients were made for
  double b0 = 1, b1 = 0, b2 = 0, a1 = 0, a2 = 0;
  double x1 = 0, x2 = 0, y1 = 0, y2 = 0;
  bool primed = false;

  // One sample at step T [s] (a change of T remakes the coefficients); returns the output.
  double filter(double x, double T);
  // The digital filter's gain at frequency f for step T (the formula above).
  static double gain(double cutoff, double f, double T);
};

class Projectile {
 public:
  explicit Projectile(const ProjectileConfig& c);

  const ProjectileConfig& config() const { return c_; }
  const RigidShape& shape() const { return shape_; }
  double mass() const { return c_.mass; }

  // The Verlet parts (see the top of the file).
  void kick(double half) { v += force * (half / c_.mass); }
  void drift(double dt) { x += v * dt; }
  // The contact pass at the current position: adds the force densities to particles.b,
  // sets force (on the body) and a = force / M.
  void contact(System& s);
  // After the step's second kick: the work of the contact force on the body over the step
  // (trapezoidal), the impulse and peaks, the filtered acceleration, at time t. `dt` 0 at
  // t = 0.
  double finish_step(const Vec3& x_before, const Vec3& force_before, double dt, double t);
  double kinetic() const { return 0.5 * c_.mass * norm2(v); }

  void checkpoint(StateArchive& a);

  // State.
  Vec3 x, v, a, force;
  Vec3 a_filtered;            // the low-pass acceleration (a itself without a filter)
  double penalty_energy = 0;  // sum V K d^(p+1)/(p+1) at the last contact pass
  Vec3 impulse;               // int force dt
  double peak_force = 0;      // max |force|
  double peak_acceleration = 0;           // max |a|
  double peak_filtered_acceleration = 0;  // max |a_filtered|
  double contact_start = -1, contact_end = -1;  // first and last time with a force

 private:
  ProjectileConfig c_;
  RigidShape shape_;
  std::array<Butterworth2, 3> filter_;
};

}  // namespace horizon
