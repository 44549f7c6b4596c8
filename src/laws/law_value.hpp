#pragma once
// Value and derivatives of an interaction law phi(d, c), c = cos(alpha), as consumed by the
// interaction kernels (paper Sec. 5.2, Eqs. 72-77 and App. E, Eqs. E1-E2).
namespace fibrane::laws {

struct LawValue {
  double value = 0, d_d = 0, d_c = 0, d_dd = 0, d_cc = 0, d_dc = 0;
  double reduced_c = 0;   // phi_{,c} / c, Eq. (75); finite as c -> 0
  double reduced_dc = 0;  // phi_{,dc} / c, Eq. (E2); finite as c -> 0
};

// Every disk law depends on the angle only through s = c^2 (the disk is symmetric under alpha ->
// -alpha), so it is evaluated in (d, s); the c-derivatives then follow by the chain rule and the
// reduced forms phi_c / c = 2 phi_s need no division by c at all.
struct DistanceSquaredCosJet {
  double value = 0, d = 0, s = 0, dd = 0, ds = 0, ss = 0;

  LawValue to_law_value(double c) const {
    LawValue out;
    out.value = value;
    out.d_d = d;
    out.d_dd = dd;
    out.reduced_c = 2.0 * s;
    out.reduced_dc = 2.0 * ds;
    out.d_c = c * out.reduced_c;
    out.d_dc = c * out.reduced_dc;
    out.d_cc = 2.0 * s + 4.0 * c * c * ss;
    return out;
  }
  DistanceSquaredCosJet& operator+=(const DistanceSquaredCosJet& o) {
    value += o.value; d += o.d; s += o.s; dd += o.dd; ds += o.ds; ss += o.ss;
    return *this;
  }
  DistanceSquaredCosJet scaled(double f) const {
    return {f * value, f * d, f * s, f * dd, f * ds, f * ss};
  }
};

}  // namespace fibrane::laws
