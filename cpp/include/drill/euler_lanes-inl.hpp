// The per-instruction-set kernel of euler_lanes.hpp, compiled once per x86 target as part of
// batched_kernel-inl.hpp (which includes it within its per-target toggle; one foreach_target.h per
// translation unit), hence no include guard. Not to be included directly.
//
// EulerPass: EulerModes::pass over the lanes in vectors of the target's width, the lanes left over one
// by one. Every lane does the scalar operations in the scalar order (separate multiplies and adds: no
// FMA, and no floating-point contraction, CMakeLists.txt), so a lane's bits are the same in a vector,
// alone, and on every target.
HWY_BEFORE_NAMESPACE();
namespace drill {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

/// EulerModes::pass on lane l alone.
HWY_INLINE void EulerPassLane(const EulerModes& e, const EulerPassIO& io, std::size_t l) {
  const std::size_t N = e.N;
  const double F = io.update ? io.F[l] : 0.0;
  double sz = 0.0, sp = 0.0, sf = 0.0, st = 0.0;
  for (int j = 0; j < e.m; ++j) {
    const std::size_t o = static_cast<std::size_t>(j) * N + l;
    const double bj = e.bit[j];
    double pj = e.p[o], zj = e.z[o];
    if (io.update) {
      pj = pj + e.dt * (e.f[o] - bj * F);  // Eq. (A.5)
      zj = zj + e.dt * pj;                 // Eq. (A.6)
      e.p[o] = pj;
      e.z[o] = zj;
    }
    sz = sz + bj * zj;
    sp = sp + bj * pj;
    if (e.top) st = st + e.top[j] * zj;
    if (e.negd) {
      double fj = e.negd[j] * pj - e.w2[j] * zj;
      if (e.force != 0.0) fj = fj + e.load[j] * e.force;
      e.f[o] = fj;
      sf = sf + bj * fj;
    }
  }
  io.bz[l] = sz;
  io.bp[l] = sp;
  if (e.negd) io.bf[l] = sf;
  if (e.top) io.tz[l] = st;
}

/// EulerModes::pass: the lanes in vectors (each vector's sums in registers over the modes), then the
/// rest one by one; the same operations as EulerPassLane.
inline void EulerPass(const EulerModes& e, const EulerPassIO& io) {
  const hn::ScalableTag<double> d;
  using V = hn::Vec<decltype(d)>;
  const std::size_t W = hn::Lanes(d), N = e.N;
  const V dt = hn::Set(d, e.dt), force = hn::Set(d, e.force);
  std::size_t l = 0;
  for (; l + W <= N; l += W) {
    V sz = hn::Zero(d), sp = sz, sf = sz, st = sz;
    const V F = io.update ? hn::LoadU(d, io.F + l) : hn::Zero(d);
    for (int j = 0; j < e.m; ++j) {
      const std::size_t o = static_cast<std::size_t>(j) * N + l;
      const V bj = hn::Set(d, e.bit[j]);
      V pj = hn::LoadU(d, e.p + o), zj = hn::LoadU(d, e.z + o);
      if (io.update) {
        pj = hn::Add(pj, hn::Mul(dt, hn::Sub(hn::LoadU(d, e.f + o), hn::Mul(bj, F))));  // Eq. (A.5)
        zj = hn::Add(zj, hn::Mul(dt, pj));                                                // Eq. (A.6)
        hn::StoreU(pj, d, e.p + o);
        hn::StoreU(zj, d, e.z + o);
      }
      sz = hn::Add(sz, hn::Mul(bj, zj));
      sp = hn::Add(sp, hn::Mul(bj, pj));
      if (e.top) st = hn::Add(st, hn::Mul(hn::Set(d, e.top[j]), zj));
      if (e.negd) {
        V fj = hn::Sub(hn::Mul(hn::Set(d, e.negd[j]), pj), hn::Mul(hn::Set(d, e.w2[j]), zj));
        if (e.force != 0.0) fj = hn::Add(fj, hn::Mul(hn::Set(d, e.load[j]), force));
        hn::StoreU(fj, d, e.f + o);
        sf = hn::Add(sf, hn::Mul(bj, fj));
      }
    }
    hn::StoreU(sz, d, io.bz + l);
    hn::StoreU(sp, d, io.bp + l);
    if (e.negd) hn::StoreU(sf, d, io.bf + l);
    if (e.top) hn::StoreU(st, d, io.tz + l);
  }
  for (; l < N; ++l) EulerPassLane(e, io, l);
}

}  // namespace HWY_NAMESPACE
}  // namespace drill
HWY_AFTER_NAMESPACE();
