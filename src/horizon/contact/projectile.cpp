#include "horizon/contact/projectile.hpp"

#include <algorithm>
#include <cmath>

#include "horizon/state/system.hpp"

namespace horizon {

double Butterworth2::filter(double x, double step) {
  if (cutoff <= 0) return x;
  if (step != T) {
    T = step;
    const double K = std::tan(M_PI * cutoff * T), r2 = std::sqrt(2.0);
    const double norm = 1 / (1 + r2 * K + K * K);
    b0 = K * K * norm;
    b1 = 2 * b0;
    b2 = b0;
    a1 = 2 * (K * K - 1) * norm;
    a2 = (1 - r2 * K + K * K) * norm;
  }
  if (!primed) {
    x1 = x2 = y1 = y2 = x;
    primed = true;
  }
  const double y = b0 * x + b1 * x1 + b2 * x2 - a1 * y1 - a2 * y2;
  x2 = x1;
  x1 = x;
  y2 = y1;
  y1 = y;
  return y;
}

double Butterworth2::gain(double cutoff, double f, double T) {
  const double r = std::tan(M_PI * f * T) / std::tan(M_PI * cutoff * T);
  return 1 / std::sqrt(1 + r * r * r * r);
}

Projectile::Projectile(const ProjectileConfig& c) : x(c.position), v(c.velocity), c_(c), shape_(c.shape) {
  for (auto& f : filter_) f.cutoff = c.filter_cutoff;
}

void Projectile::contact(System& s) {
  force = -push_particles(s, shape_, x, c_.law, c_.stiffness, &penalty_energy);
  a = force / c_.mass;
}

double Projectile::finish_step(const Vec3& x_before, const Vec3& force_before, double dt, double t) {
  const double work = 0.5 * dot(force + force_before, x - x_before);
  impulse += (force + force_before) * (0.5 * dt);
  const double T = dt > 0 ? dt : 0;
  if (c_.filter_cutoff > 0) {
    // At t = 0 the step is not known yet: the first sample primes the filter at its step.
    if (T > 0)
      for (int k = 0; k < 3; ++k) a_filtered[k] = filter_[k].filter(a[k], T);
    else
      a_filtered = a;
  } else {
    a_filtered = a;
  }
  const double f = norm(force);
  peak_force = std::max(peak_force, f);
  peak_acceleration = std::max(peak_acceleration, norm(a));
  peak_filtered_acceleration = std::max(peak_filtered_acceleration, norm(a_filtered));
  if (f > 0) {
    if (contact_start < 0) contact_start = t;
    contact_end = t;
  }
  return work;
}

void Projectile::checkpoint(StateArchive& ar) {
  ar.push(c_.name);
  ar.io("x", x);
  ar.io("v", v);
  ar.io("a", a);
  ar.io("force", force);
  ar.io("a_filtered", a_filtered);
  ar.io("penalty_energy", penalty_energy);
  ar.io("impulse", impulse);
  ar.io("peak_force", peak_force);
  ar.io("peak_acceleration", peak_acceleration);
  ar.io("peak_filtered_acceleration", peak_filtered_acceleration);
  ar.io("contact_start", contact_start);
  ar.io("contact_end", contact_end);
  for (int k = 0; k < 3; ++k) {
    Butterworth2& f = filter_[k];
    const std::string n = "filter" + std::to_string(k);
    double st[10] = {f.T, f.b0, f.b1, f.b2, f.a1, f.a2, f.x1, f.x2, f.y1, f.y2};
    double primed = f.primed ? 1 : 0;
    for (int q = 0; q < 10; ++q) ar.io(n + "_" + std::to_string(q), st[q]);
    ar.io(n + "_primed", primed);
    if (ar.loading()) {
      f.T = st[0], f.b0 = st[1], f.b1 = st[2], f.b2 = st[3], f.a1 = st[4], f.a2 = st[5];
      f.x1 = st[6], f.x2 = st[7], f.y1 = st[8], f.y2 = st[9];
      f.primed = primed != 0;
    }
  }
  ar.pop();
}

}  // namespace horizon
