// The fixed cost of a Kokkos kernel launch on the device machine (issue: the 2D step at 18k
// particles is a sum of such costs): empty kernels over N = 18,272 indices, launched M times,
// with a small functor and with one of 3 KB (the size of sphcut's contact and pair functors),
// through the kernel-argument path (HintLightWeight, what sphcut::range asks for) and Kokkos'
// default (constant memory above 512 bytes), and reductions into a device View and into a host
// scalar, and reductions of 4 and 12 sums with a final (the integrator's corrector and the
// contact kernel) as a runtime-sized array (value_type[]) and as a struct, over N and over 21
// indices (the contact kernel's near list).  For each: the host's time per launch (submission only: no fence inside the loop) and
// the time per launch with one fence at the end (what the device takes when the host is ahead).
// Build: cmake -S bench/gpu/launch -B build-launch -DKokkos_DIR=<prefix>/lib/cmake/Kokkos
#include <Kokkos_Core.hpp>

#include <chrono>
#include <cstdio>

namespace {
double now()
{
  using namespace std::chrono;
  return duration<double>(steady_clock::now().time_since_epoch()).count();
}

struct Small {
  Kokkos::View<double *> a;
  KOKKOS_INLINE_FUNCTION void operator()(const int i) const
  {
    if (i < 0) a(0) = 1.0;
  }
};

struct Big {
  Kokkos::View<double *> a;
  double pad[380];    // 3 KB of constants, as a functor with many Views and parameters
  KOKKOS_INLINE_FUNCTION void operator()(const int i) const
  {
    if (i < 0) a(0) = pad[i & 7];
  }
};

struct BigReduce {
  Kokkos::View<double *> a;
  double pad[380];
  KOKKOS_INLINE_FUNCTION void operator()(const int i, double &m) const
  {
    m = m < a(i) ? a(i) : m;
  }
};

// an array reduction of NV sums with a final that adds them to acc (device View)
template <int NV> struct Sums {
  typedef double value_type[];
  const int value_count = NV;
  Kokkos::View<double *> a, acc;
  KOKKOS_INLINE_FUNCTION void init(value_type r) const
  {
    for (int k = 0; k < NV; k++) r[k] = 0.0;
  }
  KOKKOS_INLINE_FUNCTION void join(volatile value_type d, const volatile value_type s) const
  {
    for (int k = 0; k < NV; k++) d[k] += s[k];
  }
  KOKKOS_INLINE_FUNCTION void operator()(const int i, value_type r) const
  {
    for (int k = 0; k < NV; k++) r[k] += a(i);
  }
  KOKKOS_INLINE_FUNCTION void final(value_type r) const
  {
    for (int k = 0; k < NV; k++) acc(k) += r[k];
  }
};

// the same sums as one value of fixed size (a struct): Kokkos reduces it with warp shuffles
template <int NV> struct Fixed {
  double v[NV];
};
template <int NV> struct FixedSums {
  typedef Fixed<NV> value_type;
  Kokkos::View<double *> a, acc;
  KOKKOS_INLINE_FUNCTION void init(value_type &r) const
  {
    for (int k = 0; k < NV; k++) r.v[k] = 0.0;
  }
  KOKKOS_INLINE_FUNCTION void join(volatile value_type &d, const volatile value_type &s) const
  {
    for (int k = 0; k < NV; k++) d.v[k] += s.v[k];
  }
  KOKKOS_INLINE_FUNCTION void operator()(const int i, value_type &r) const
  {
    for (int k = 0; k < NV; k++) r.v[k] += a(i);
  }
  KOKKOS_INLINE_FUNCTION void final(value_type &r) const
  {
    for (int k = 0; k < NV; k++) acc(k) += r.v[k];
  }
};

// M reductions of functor f over n indices into the device View out, back to back
template <class F, class Out> void time_reduce(const char *what, const F &f, const Out &out, int n, int m)
{
  auto pol = Kokkos::Experimental::require(Kokkos::RangePolicy<>(0, n), Kokkos::Experimental::WorkItemProperty::HintLightWeight);
  for (int k = 0; k < 100; k++) Kokkos::parallel_reduce("lr", pol, f, out);
  Kokkos::fence();
  double t0 = now();
  for (int k = 0; k < m; k++) Kokkos::parallel_reduce("lr", pol, f, out);
  double t1 = now();
  Kokkos::fence();
  double t2 = now();
  std::printf("%-44s %5zu B: host %6.2f us/launch, with the device %6.2f us/launch\n", what, sizeof(f),
              1e6 * (t1 - t0) / m, 1e6 * (t2 - t0) / m);
}

// NV sums over n indices and a final, as an array (Sums) and as a struct (FixedSums)
template <int NV> void time_sums(int n, int m)
{
  Kokkos::View<double *> a("a", n > 0 ? n : 1), acc("acc", NV);
  char what[80];
  Sums<NV> f;
  f.a = a;
  f.acc = acc;
  std::snprintf(what, sizeof(what), "%d sums and a final into a device View, n = %d", NV, n);
  time_reduce(what, f, Kokkos::View<double *>("out", NV), n, m);
  FixedSums<NV> g;
  g.a = a;
  g.acc = acc;
  std::snprintf(what, sizeof(what), "%d sums (a struct) and a final, n = %d", NV, n);
  time_reduce(what, g, Kokkos::View<Fixed<NV>>("out"), n, m);
}

template <class F> void time_for(const char *what, const F &f, int n, int m, bool light)
{
  auto run = [&]() {
    if (light)
      Kokkos::parallel_for("lo", Kokkos::Experimental::require(Kokkos::RangePolicy<>(0, n),
                                                                Kokkos::Experimental::WorkItemProperty::HintLightWeight), f);
    else
      Kokkos::parallel_for("lo", Kokkos::RangePolicy<>(0, n), f);
  };
  for (int k = 0; k < 100; k++) run();
  Kokkos::fence();
  double t0 = now();
  for (int k = 0; k < m; k++) run();
  double t1 = now();
  Kokkos::fence();
  double t2 = now();
  std::printf("%-44s %5zu B: host %6.2f us/launch, with the device %6.2f us/launch\n", what, sizeof(F),
              1e6 * (t1 - t0) / m, 1e6 * (t2 - t0) / m);
}
}    // namespace

int main(int argc, char **argv)
{
  Kokkos::initialize(argc, argv);
  {
    const int n = 18272, m = 5000;
    Kokkos::View<double *> a("a", n);
    Small s{a};
    Big b;
    b.a = a;
    for (double &p : b.pad) p = 0.0;
    time_for("empty for, small functor", s, n, m, false);
    time_for("empty for, small functor, light", s, n, m, true);
    time_for("empty for, 3 KB functor (constant memory)", b, n, m, false);
    time_for("empty for, 3 KB functor, light (argument)", b, n, m, true);
    time_for("empty for, small functor, light, n = 1", s, 1, m, true);
    BigReduce r;
    r.a = a;
    for (double &p : r.pad) p = 0.0;
    Kokkos::View<double> d("d");
    auto pol = Kokkos::Experimental::require(Kokkos::RangePolicy<>(0, n), Kokkos::Experimental::WorkItemProperty::HintLightWeight);
    for (int k = 0; k < 100; k++) Kokkos::parallel_reduce("lr", pol, r, Kokkos::Max<double, Kokkos::DefaultExecutionSpace::memory_space>(d));
    Kokkos::fence();
    double t0 = now();
    for (int k = 0; k < m; k++) Kokkos::parallel_reduce("lr", pol, r, Kokkos::Max<double, Kokkos::DefaultExecutionSpace::memory_space>(d));
    double t1 = now();
    Kokkos::fence();
    double t2 = now();
    std::printf("%-44s %5zu B: host %6.2f us/launch, with the device %6.2f us/launch\n",
                "max reduce into a device View, light", sizeof(r), 1e6 * (t1 - t0) / m, 1e6 * (t2 - t0) / m);
    double h = 0.0;
    t0 = now();
    for (int k = 0; k < m; k++) Kokkos::parallel_reduce("lh", pol, r, Kokkos::Max<double>(h));
    t1 = now();
    std::printf("%-44s %5zu B: %6.2f us/launch (each waits for its result)\n", "max reduce into a host scalar, light",
                sizeof(r), 1e6 * (t1 - t0) / m);
    for (const int rows : {n, 21}) {
      time_sums<4>(rows, m);
      time_sums<12>(rows, m);
    }
  }
  Kokkos::finalize();
  return 0;
}
