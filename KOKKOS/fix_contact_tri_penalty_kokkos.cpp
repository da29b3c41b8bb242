/* ----------------------------------------------------------------------
   sphcut - fix contact/tri-penalty/kk

   post_force, on the device:
     kernel 1 (one reduction over the local particles near the tool,
       near_build: the others would change nothing): each particle's
       contact step (sphcut_contact_step.h contact_step, the CPU fix's
       too): the energy of the previous step's contact force, the nearest
       tool element within 2h, the spring's dt limit, the contact
       (penalty_contact), the force added to f, the friction heat to the
       particle (its temperature rate) and, for the tool's share, the heat
       per kernel weight of the tool particles around it (ContactKernel::Sink)
     forward communication of that heat per weight to the ghosts
     kernel 2 (the tool particles next to non-tool ones): each gathers the
       heat of the contact particles around it, kernel weighted (the CPU fix
       scatters the same sums to the tool particles)
   Both walk the cross neighbours, not the whole neighbour list: a scan at
   each reneighbouring (cross_build) keeps, in the list's order, a contact
   candidate's tool neighbours and a tool particle's non-tool neighbours,
   and the tool particles that have some (the gather's range).  Per step
   the fix launches these two kernels (and, on several ranks, the forward
   communication's); the gather cannot wait for fix heat/fmfs's evaluation
   steps: the temperature rate it adds is integrated every step.
   The host gets the sums of kernel 1 (tool force, work, dissipation,
   friction power, contact count, deepest penetration, heat booked, the
   spring's dt limit) and updates the tool's position and velocity.
   Kernel 1 also leaves a record of each contact (sphcut::contact_record,
   the feature, the penetration): the decomposition by tool feature
   (vector 16-47) and the deepest penetration (12) are formed from them by
   a third kernel only when a consumer reads them (record_sums()).  The
   accumulators that fetch() has read are zeroed by kernel 1 of the next
   step (no fill kernel on output steps).
------------------------------------------------------------------------- */

#include "fix_contact_tri_penalty_kokkos.h"

#include "atom_kokkos.h"
#include "atom_masks.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix_heat_fmfs.h"
#include "fix_sph_jc_thermal_kokkos.h"
#include "memory_kokkos.h"
#include "neigh_list_kokkos.h"
#include "neighbor.h"
#include "output.h"
#include "sphcut_model.h"
#include "update.h"

#include "sphcut_compat.h"
#include "sphcut_kernels.h"
#include "sphcut_kokkos.h"
#include "sphcut_thermal.h"

#include <algorithm>
#include <cstdint>
#include <vector>

using namespace LAMMPS_NS;
using namespace FixConst;

namespace {

// the sums of the contact kernel: R_FX.. are added, R_DTCRIT minimised; the first ten are
// sphcut::contact_step's sums (sphcut::ContactSum, the same numbers).  R_TWORK and R_DISS hold both
// rates of the step's trapezoid, the previous contact force's and this one's (the host needs only
// their sum).  Not among them: the contacts (counted by the slots of their records), the
// decomposition by tool feature and the deepest penetration (from the records, when they are
// read: record_sums())
enum {
  R_FX = sphcut::CS_FX, R_FY, R_FZ, R_TWORK = sphcut::CS_WORK, R_DISS = sphcut::CS_DISS, R_FRIC = sphcut::CS_FRIC,
  R_QWORK = sphcut::CS_QWORK, R_QLOST, R_QLUMP, R_QTOOL = sphcut::CS_QTOOL, R_QSRC, R_TORQUE, R_DTCRIT, NRED
};
static_assert((int) R_FZ == (int) sphcut::CS_FZ && (int) R_QLUMP == (int) sphcut::CS_QLUMP,
              "the reduction's sums follow sphcut::ContactSum");

// the device accumulators after the NRED sums of the last step (FixContactTriPenaltyKokkos::d_sums):
// what the host adds to its totals when it next reads them (fetch)
enum { A_QWORK = 0, A_QLOST, A_QTOOL, A_QSRC, A_QLUMP, A_TWORK, A_DISS, NACCUM };

// then the two counters of the contact records (d_sums(C_NREC + 0 or 1), used in turn), so
// that fetch() brings the number of contacts with the sums; then the sums R_FX .. R_QSRC of the
// running evaluation (S_RUN + c), which its particles add to by atomics (only those with something
// to add: the few in contact) and its final moves to d_sums(c)
enum { C_NREC = NRED + NACCUM, S_RUN = C_NREC + 2, NSUMS = S_RUN + R_DTCRIT };

// the kernel reduces only the smallest spring dt (a scalar: Kokkos 3.4 reduces an array of sums in a
// shared-memory tree whose launch costs more with each sum: bench/gpu/launch, RESULTS.md "The
// launch floor"); the sums go by atomics, and final
// (one thread after all the others) publishes them as the step's
template <class DeviceType> struct ContactKernel {
  typedef DeviceType device_type;
  typedef double value_type;
  typedef ArrayTypes<DeviceType> AT;
  typedef typename DeviceType::memory_space mem;
  using SL = sphcut::StateLayout;
  sphcut::ContactStep step;    // the same for every particle (FixContactTriPenalty::step_params, device copies)
  typename sphcut::AtomTypes<DeviceType>::x_const x;
  typename sphcut::AtomTypes<DeviceType>::v_const v;
  typename sphcut::AtomTypes<DeviceType>::f f;
  typename AT::t_int_1d_const mask, type;
  typename sphcut::AtomTypes<DeviceType>::scalar_const rmass, mass;
  typename AT::t_double_2d state;
  typename AT::t_double_2d qtw;       // tool heat per kernel weight, the particle's position
  typename AT::t_double_2d fout;    // per-atom output: force (3), F_N, |F_T|, feature
  Kokkos::View<const sphcut::Material *, mem> mat;
  Kokkos::View<const double *, mem> h, dp, hij;
  ContactMaskBits bits;
  int use_rmass, ntp, kernel;
  Kokkos::View<double *, mem> sums;    // NRED sums of this step, the NACCUM accumulators, the counters
  typename AT::t_double_1d dtlim;      // the spring's dt limit: this fix's slot of fix sph/jc-thermal/kk
  double dtscale;                      // dtfac * cfl (FixContactTriPenalty::dt_limit)
  // one record per contact (sphcut::contact_record, the feature, the penetration), in the order
  // the contacts take a slot from the counter sums(C_NREC + cur); the other is cleared (final)
  typedef FixContactTriPenaltyKokkos<DeviceType> FK;
  Kokkos::View<double *[FK::NREC], mem> rec;
  int cur;
  Kokkos::View<double *, mem> facc;    // tool fields per facet: the running interval's sums
  Kokkos::View<const int *, mem> xoff, xnb;    // the cross neighbours (cross_build): a candidate's tool neighbours
  int reset;                           // zero the accumulators first (fetch() has read them)
  Kokkos::View<const int *, mem> near;  // the particles to evaluate (near_build)

  KOKKOS_INLINE_FUNCTION void init(value_type &dtcrit) const { dtcrit = 1.0e300; }
  KOKKOS_INLINE_FUNCTION void join(SPHCUT_KK_VOLATILE value_type &d, const SPHCUT_KK_VOLATILE value_type &s) const
  {
    if (s < d) d = s;
  }
  // once, on the device, after every particle: the step's sums from their running copies (zeroed
  // for the next evaluation), the time integrals (as the CPU fix's post_force) and the dt limit
  // stay on the device; the host reads them when it needs them
  KOKKOS_INLINE_FUNCTION void final(value_type &dtcrit) const
  {
    for (int c = 0; c < R_DTCRIT; c++) {
      sums(c) = sums(S_RUN + c);
      sums(S_RUN + c) = 0.0;
    }
    sums(R_DTCRIT) = dtcrit;
    double r[NRED];
    for (int c = 0; c < NRED; c++) r[c] = sums(c);
    if (reset)
      for (int a = 0; a < NACCUM; a++) sums(NRED + a) = 0.0;
    sums(NRED + A_QWORK) += r[R_QWORK];
    sums(NRED + A_QLOST) += r[R_QLOST];
    sums(NRED + A_QTOOL) += r[R_QTOOL];
    sums(NRED + A_QSRC) += r[R_QSRC];
    sums(NRED + A_QLUMP) += r[R_QLUMP];
    if (!step.setup) {
      sums(NRED + A_TWORK) += 0.5 * step.dt * r[R_TWORK];
      sums(NRED + A_DISS) += 0.5 * step.dt * r[R_DISS];
    }
    dtlim(0) = r[R_DTCRIT] < 1.0e300 ? dtscale * r[R_DTCRIT] : 1.0e300;
    sums(C_NREC + 1 - cur) = 0.0;
  }

  // particle i as sphcut::contact_step sees it: reads of the views, writes into the views and
  // this thread's sums r
  struct Sink {
    const ContactKernel &k;
    const int i, it;    // it: the type (candidates only)
    double *r;
    KOKKOS_INLINE_FUNCTION double v(int d) const { return k.v(i, d); }
    KOKKOS_INLINE_FUNCTION double x(int d) const { return k.x(i, d); }
    KOKKOS_INLINE_FUNCTION double f(int d) const { return k.f(i, d); }
    KOKKOS_INLINE_FUNCTION double h() const { return k.h(it); }
    KOKKOS_INLINE_FUNCTION double spacing() const { return k.dp(it); }
    KOKKOS_INLINE_FUNCTION double E() const { return k.mat(it).E; }
    KOKKOS_INLINE_FUNCTION double mass() const { return k.use_rmass ? k.rmass(i) : k.mass(it); }
    KOKKOS_INLINE_FUNCTION double *state() const { return &k.state(i, 0); }
    KOKKOS_INLINE_FUNCTION double *output() const { return &k.fout(i, 0); }
    // the reduction holds both halves of the step's work and dissipation in one sum each
    KOKKOS_INLINE_FUNCTION void add(int c, double val) const
    {
      r[c == sphcut::CS_WORK_OLD ? R_TWORK
                                 : (c == sphcut::CS_DISS_OLD ? R_DISS : (c == sphcut::CS_TORQUE ? R_TORQUE : c))] += val;
    }
    KOKKOS_INLINE_FUNCTION void add_force(int d, double val) const { k.f(i, d) += val; }
    KOKKOS_INLINE_FUNCTION void dt_crit(double d) const
    {
      if (d < r[R_DTCRIT]) r[R_DTCRIT] = d;
    }
    // the record (decomposition by tool feature, penetration) in the next slot
    KOKKOS_INLINE_FUNCTION void record(int feat, const double *dr, double pen) const
    {
      const int slot = (int) Kokkos::atomic_fetch_add(&k.sums(C_NREC + k.cur), 1.0);
      if (slot < (int) k.rec.extent(0)) {    // (always: one slot per local particle)
        for (int c = 0; c < sphcut::NDREC; c++) k.rec(slot, c) = dr[c];
        k.rec(slot, FK::REC_FEAT) = feat;
        k.rec(slot, FK::REC_PEN) = pen;
      }
    }
    KOKKOS_INLINE_FUNCTION void facet(int fct, const double *c) const
    {
      for (int j = 0; j < sphcut::NFS; j++) Kokkos::atomic_add(&k.facc(fct * sphcut::NFS + j), c[j]);
    }
    // heat into the particle's temperature rate, as FixHeatFMFS::add_heat
    KOKKOS_INLINE_FUNCTION void heat_particle(double q, double m, double acc) const
    {
      if (!(k.mask(i) & k.bits.heat)) return;
      if (!sphcut::add_source_heat(k.state(i, SL::DTEMP), q, m, k.mat(it).cp)) return;
      r[R_QSRC] += q * acc;
    }
    // the tool particles within the kernel support share q by kernel weight: the heat per
    // weight here, gathered by them in tool_heat_gather.  The tool neighbours of the list, in
    // its order (the cross neighbours: the same sum as over the whole list)
    KOKKOS_INLINE_FUNCTION bool heat_tool(double q) const
    {
      double wsum = 0.0;
      for (int c = k.xoff(i); c < k.xoff(i + 1); c++) {
        const int j = k.xnb(c);
        if (!(k.mask(j) & k.bits.tool)) continue;
        double r2 = 0.0;
        for (int d = 0; d < 3; d++) r2 += (k.x(i, d) - k.x(j, d)) * (k.x(i, d) - k.x(j, d));
        wsum += sphcut::tool_heat_weight(k.kernel, k.step.base.dim, r2, k.hij(it * k.ntp + k.type(j)));
      }
      if (!(wsum > 0.0)) return false;
      k.qtw(i, 0) = q / wsum;
      for (int d = 0; d < 3; d++) k.qtw(i, 1 + d) = k.x(i, d);    // where the gather finds it (ToolHeatGather)
      return true;
    }
  };

  KOKKOS_INLINE_FUNCTION void operator()(const int ii, value_type &dtcrit) const
  {
    const int i = near(ii);
    qtw(i, 0) = 0.0;
    const bool candidate = bits.candidate(mask(i));
    double r[NRED];    // this particle's share of the sums
    for (int c = 0; c < R_DTCRIT; c++) r[c] = 0.0;
    r[R_DTCRIT] = dtcrit;
    Sink sink{*this, i, candidate ? type(i) : 0, r};
    sphcut::contact_step(step, candidate, sink);
    for (int c = 0; c < R_DTCRIT; c++)
      if (r[c] != 0.0) Kokkos::atomic_add(&sums(S_RUN + c), r[c]);
    dtcrit = r[R_DTCRIT];
  }
};

// the contact kernel on sphcut::reduce's wide path (its one value, the smallest spring dt, a
// minimum).  Its final, run by the last warp to join, reads the sums every particle added by
// atomics (sums(S_RUN + c), the record counter): each particle's thread fences after its own, so
// that they are visible before its warp counts itself done
template <class DeviceType> struct ContactWide {
  ContactKernel<DeviceType> k;
  KOKKOS_INLINE_FUNCTION static constexpr bool is_min(int) { return true; }
  KOKKOS_INLINE_FUNCTION void init(double *r) const { k.init(r[0]); }
  KOKKOS_INLINE_FUNCTION void operator()(const int ii, double *r) const
  {
    k(ii, r[0]);
    Kokkos::memory_fence();
  }
  KOKKOS_INLINE_FUNCTION void final(double *r) const { k.final(r[0]); }
};

// the cross neighbours of each local particle, in the order of its neighbour list: a contact
// candidate's tool neighbours, a tool particle's other neighbours (none for the rest); xoff(i)
// to xoff(i + 1) in xnb.  The scan's value holds the entries in its low 32 bits and, above,
// the tool particles of the heat group that have some (xtool, the gather's range).  Entries
// beyond xnb's size are counted, not written (the caller grows xnb and scans again).
template <class DeviceType> struct CrossKernel {
  typedef DeviceType device_type;
  typedef int64_t value_type;
  typedef ArrayTypes<DeviceType> AT;
  typedef typename DeviceType::memory_space mem;
  static constexpr int64_t LOW = 0xffffffffLL, GATHER = 1LL << 32;
  typename AT::t_int_1d_const mask;
  typename AT::t_neighbors_2d neighbors;
  typename AT::t_int_1d_const numneigh;
  Kokkos::View<int *, mem> xoff, xnb, xtool;
  ContactMaskBits bits;

  KOKKOS_INLINE_FUNCTION void operator()(const int i, value_type &upd, const bool final) const
  {
    const int m = mask(i);
    const bool tool = m & bits.tool;
    const int start = (int) (upd & LOW);
    int c = 0;
    if (tool || bits.candidate(m)) {
      const int nn = numneigh(i);
      for (int jj = 0; jj < nn; jj++) {
        const int j = neighbors(i, jj) & NEIGHMASK;
        if (((mask(j) & bits.tool) != 0) == tool) continue;
        if (final && start + c < (int) xnb.extent(0)) xnb(start + c) = j;
        c++;
      }
    }
    const bool gather = tool && (m & bits.heat) && c > 0;
    if (final) {
      if (i == 0) xoff(0) = 0;
      xoff(i + 1) = start + c;
      if (gather) xtool((int) (upd >> 32)) = i;
    }
    upd += c + (gather ? GATHER : 0);
  }
};

// the contact kernel's particles (FixContactTriPenaltyKokkos::near_build): the local contact
// candidates whose tool-frame position lies within slack of the tool's bin grid; the others get
// their heat per weight and per-atom contact output cleared (after a reneighbouring a row may
// hold another atom's values; the kernel clears them for the particles it evaluates)
template <class DeviceType> struct NearKernel {
  typedef DeviceType device_type;
  typedef int value_type;
  typedef ArrayTypes<DeviceType> AT;
  typedef typename DeviceType::memory_space mem;
  typename sphcut::AtomTypes<DeviceType>::x_const x;
  typename AT::t_int_1d_const mask;
  typename AT::t_double_2d qtw, fout;
  Kokkos::View<int *, mem> near;
  ContactMaskBits bits;
  double lo[3], hi[3];    // the grid's box widened by the slack, tool frame
  double disp[3];
  sphcut::ToolRotation rot;    // a rotating tool: the particles turned into the tool frame
  int ndim;               // 2: segments (x, y), 3: triangles
  int none;               // 1: the tool has no element (nobody is near)

  KOKKOS_INLINE_FUNCTION void operator()(const int i, int &upd, const bool final) const
  {
    bool in = !none && bits.candidate(mask(i));
    if (in && rot.on) {
      const double xs[3] = {x(i, 0), x(i, 1), x(i, 2)};
      double xt[3];
      sphcut::tool_frame_point(disp, rot, xs, ndim, xt);
      for (int k = 0; k < ndim && in; k++) in = xt[k] >= lo[k] && xt[k] <= hi[k];
    }
    for (int k = 0; k < ndim && in && !rot.on; k++) {
      const double xt = x(i, k) - disp[k];
      in = xt >= lo[k] && xt <= hi[k];
    }
    if (final) {
      if (in) {
        near(upd) = i;
      } else {
        qtw(i, 0) = 0.0;
        for (int c = 0; c < 6; c++) fout(i, c) = 0.0;
      }
    }
    upd += in ? 1 : 0;
  }
};

// from the records of the contact kernel: the decomposition by tool feature
// (FixContactTriPenalty::decomp, NFEAT x NDECOMP), then the deepest penetration (maxpen)
template <class DeviceType> struct RecordKernel {
  typedef DeviceType device_type;
  typedef double value_type[];
  typedef typename DeviceType::memory_space mem;
  typedef FixContactTriPenaltyKokkos<DeviceType> FK;
  enum { NDECOMP = FixContactTriPenalty::NDECOMP, V_MAXPEN = FixContactTriPenalty::NFEAT * NDECOMP, NV };
  const unsigned value_count = NV;
  Kokkos::View<const double *[FK::NREC], mem> rec;

  KOKKOS_INLINE_FUNCTION void init(value_type r) const
  {
    for (int k = 0; k < NV; k++) r[k] = 0.0;
  }
  KOKKOS_INLINE_FUNCTION void join(SPHCUT_KK_VOLATILE value_type d, const SPHCUT_KK_VOLATILE value_type s) const
  {
    for (int k = 0; k < V_MAXPEN; k++) d[k] += s[k];
    if (s[V_MAXPEN] > d[V_MAXPEN]) d[V_MAXPEN] = s[V_MAXPEN];
  }
  KOKKOS_INLINE_FUNCTION void operator()(const int c, value_type r) const
  {
    double dr[sphcut::NDREC];
    for (int k = 0; k < sphcut::NDREC; k++) dr[k] = rec(c, k);
    const int feat = (int) rec(c, FK::REC_FEAT);
    sphcut::decompose_record(dr, r + feat * NDECOMP);
    if (rec(c, FK::REC_PEN) > r[V_MAXPEN]) r[V_MAXPEN] = rec(c, FK::REC_PEN);
  }
};

}    // namespace

/* ---------------------------------------------------------------------- */

template <class DeviceType>
FixContactTriPenaltyKokkos<DeviceType>::FixContactTriPenaltyKokkos(LAMMPS *lmp, int narg, char **arg) :
    FixContactTriPenalty(sphcut::require_kokkos(lmp, "Fix contact/tri-penalty/kk"), narg, arg), fixkk(nullptr)
{
  if (friction.host_only())
    error->all(FLERR, "Fix contact/tri-penalty/kk: mu v_{} (a LAMMPS variable per particle) cannot be "
               "evaluated on the device; give mu as a number or a table (mu table T1 mu1 T2 mu2 ...), or "
               "run without /kk", mu_var);
  kokkosable = 1;
  forward_comm_device = 1;
  comm_forward = 1;
  atomKK = (AtomKokkos *) atom;
  execution_space = ExecutionSpaceFromDevice<DeviceType>::space;
  datamask_read = X_MASK | V_MASK | F_MASK | MASK_MASK | TYPE_MASK | RMASS_MASK;
  datamask_modify = F_MASK;
  // the per-atom output lives in a DualView (grown in post_force)
  memory->destroy(fcontact);
  fcontact = nullptr;
  nmax_out = 0;
}

template <class DeviceType> FixContactTriPenaltyKokkos<DeviceType>::~FixContactTriPenaltyKokkos()
{
  memoryKK->destroy_kokkos(k_fout, fcontact);
  fcontact = nullptr;    // the base destructor must not free it
}

// restart files match fixes by ID and style: the /kk fix goes by the CPU style's name
template <class DeviceType> void FixContactTriPenaltyKokkos<DeviceType>::post_constructor()
{
  delete[] style;
  style = utils::strdup("contact/tri-penalty");
}

template <class DeviceType> void FixContactTriPenaltyKokkos<DeviceType>::init()
{
  // the CPU init reads positions, masks and types on the host (split auto, the first dt limit)
  atomKK->sync(Host, X_MASK | V_MASK | MASK_MASK | TYPE_MASK | RMASS_MASK);
  FixContactTriPenalty::init();
  if (toolbit) sphcut::kokkos_full_list<DeviceType>(neighbor);
  fixkk = dynamic_cast<FixSPHJCThermalKokkosBase *>(fix);
  if (!fixkk) error->all(FLERR, "Fix contact/tri-penalty/kk requires fix sph/jc-thermal/kk (run with -sf kk)");
  const sphcut::HookArm<DeviceType> arm = [this](sphcut::IntegratorHooks<DeviceType> &h,
                                                 const sphcut::HookCall &c) { arm_hook(h, c); };
  hooked = fixkk->set_hook<DeviceType>(this, sphcut::HOOK_TOOL_HEAT, arm);
  gather_step = -1;
  wide = sphcut::wide_choice<DeviceType>(lmp, "Fix contact/tri-penalty/kk");
  near_calls = -1;    // built again at the setup
  if (heat && !heat->kokkosable)
    error->all(FLERR, "Fix contact/tri-penalty/kk: heat fix {} is not fix heat/fmfs/kk (run with -sf kk)", id_heat);
  upload();
  fields_upload();
  peratom_freq = fix->peratom_freq;    // the per-atom contact force comes to the host with the state
}

template <class DeviceType> void FixContactTriPenaltyKokkos<DeviceType>::upload()
{
  d_elem = sphcut::to_device<double, DeviceType>(bins.elem.data(), (int) bins.elem.size(), "contact:elem");
  d_sphere = sphcut::to_device<double, DeviceType>(bins.sphere.data(), (int) bins.sphere.size(), "contact:sphere");
  d_start = sphcut::to_device<int, DeviceType>(bins.start.data(), (int) bins.start.size(), "contact:start");
  d_index = sphcut::to_device<int, DeviceType>(bins.index.data(), (int) bins.index.size(), "contact:index");
  d_pnorm = sphcut::to_device<double, DeviceType>(bins.pnorm.data(), (int) bins.pnorm.size(), "contact:pnorm");
  d_view = bins.view();
  d_view.elem = d_elem.data();
  d_view.sphere = d_sphere.data();
  d_view.start = d_start.data();
  d_view.index = d_index.data();
  d_view.pnorm = bins.pnorm.empty() ? nullptr : d_pnorm.data();
  const int n = atom->ntypes + 1;
  d_mat = sphcut::to_device<sphcut::Material, DeviceType>(model->materials(), n, "contact:mat");
  std::vector<double> h(n, 0.0), dp(n, 0.0), hij((size_t) n * n, 0.0);
  for (int i = 1; i < n; i++) {
    h[i] = model->smoothing_length(i);
    dp[i] = model->spacing(i);
    for (int j = 1; j < n; j++) hij[(size_t) i * n + j] = model->smoothing_length(i, j);
  }
  d_h = sphcut::to_device<double, DeviceType>(h.data(), n, "contact:h");
  d_dp = sphcut::to_device<double, DeviceType>(dp.data(), n, "contact:dp");
  d_hij = sphcut::to_device<double, DeviceType>(hij.data(), n * n, "contact:hij");
  const int nmu = (int) mu_t.size();    // the friction law's table mu(T), if any
  std::vector<double> t(mu_t), m(mu_v);
  t.resize(nmu + 1, 0.0);
  m.resize(nmu + 1, 0.0);
  d_mut = sphcut::to_device<double, DeviceType>(t.data(), nmu + 1, "contact:mut");
  d_muv = sphcut::to_device<double, DeviceType>(m.data(), nmu + 1, "contact:muv");
  std::vector<int> feat(elem_feature);
  feat.resize(bins.elem.size() / (nvert == 3 ? 9 : 6) + 1, FEAT_OTHER);
  d_feature = sphcut::to_device<int, DeviceType>(feat.data(), (int) feat.size(), "contact:feature");
}

/* setup as the CPU fix (host), then the forces of the setup step on the device */
template <class DeviceType> void FixContactTriPenaltyKokkos<DeviceType>::setup(int vflag)
{
  atomKK->sync(Host, X_MASK | V_MASK | MASK_MASK | TYPE_MASK);
  fixkk->k_state.sync_host();
  update_tool_velocity();
  for (int d = 0; d < 3; d++) vtool_dev[d] = vtool[d];
  atomKK->modified(Host, V_MASK);
  if (!inside_checked) {
    warn_inside();
    if (!restored) clear_history();
    fixkk->k_state.modify_host();
  }
  fields_at_setup();    // as the CPU fix's setup (host: the pose, no device sums)
  inside_checked = 1;
  xcalls = -1;    // the cross neighbours from this setup's lists (masks may have changed between runs)
  post_force(vflag);
  fetch();
  if (write_every) write_geometry();
}

/* ---------------------------------------------------------------------- */

template <class DeviceType> void FixContactTriPenaltyKokkos<DeviceType>::post_force(int)
{
  sphcut::FencedTimer timer(cpu_time);
  atomKK->sync(execution_space, datamask_read);
  fixkk->k_state.template sync<DeviceType>();
  if ((int) k_qtw.extent(0) < atom->nmax) k_qtw = DAT::tdual_double_2d("contact:qtw", atom->nmax, 4);
  k_qtw.template sync<DeviceType>();
  if (atom->nmax > nmax_out) {
    nmax_out = atom->nmax;
    k_fout.template sync<DeviceType>();
    k_fout.template modify<DeviceType>();
    memoryKK->grow_kokkos(k_fout, fcontact, nmax_out, 6, "contact:fout");
    array_atom = fcontact;
  }
  k_fout.template sync<DeviceType>();
  const double dt = update->dt;
  if (!update->setupflag || dt_last <= 0.0) dt_last = dt;

  ContactKernel<DeviceType> k;
  // what is the same for every particle, with the device copies of the tool and its facet tables
  k.step = step_params(dt_last);
  k.step.tool = d_view;
  k.step.feature = d_feature.data();
  k.step.share.start = d_share_start.data();
  k.step.share.elem = d_share_elem.data();
  k.step.inv_area = d_inv_area.data();
  k.step.base.friction.mu_t = d_mut.data();    // (the friction law's table mu(T), used if it has one)
  k.step.base.friction.mu_v = d_muv.data();
  k.x = atomKK->k_x.view<DeviceType>();
  k.v = atomKK->k_v.view<DeviceType>();
  k.f = atomKK->k_f.view<DeviceType>();
  k.mask = atomKK->k_mask.view<DeviceType>();
  k.type = atomKK->k_type.view<DeviceType>();
  k.rmass = atomKK->k_rmass.view<DeviceType>();
  k.mass = atomKK->k_mass.view<DeviceType>();
  k.state = fixkk->k_state.template view<DeviceType>();
  k.qtw = k_qtw.template view<DeviceType>();
  k.fout = k_fout.template view<DeviceType>();
  k.mat = d_mat;
  k.h = d_h;
  k.dp = d_dp;
  k.hij = d_hij;
  k.bits = mask_bits();
  k.use_rmass = atom->rmass_flag;
  k.ntp = atom->ntypes + 1;
  k.kernel = model->kernel();
  if ((int) d_sums.extent(0) != NSUMS) {
    d_sums = Kokkos::View<double *, mem>("contact:sums", NSUMS);    // zeroed (the counters too)
    h_sums = Kokkos::create_mirror_view(d_sums);
  }
  k.sums = d_sums;
  if ((int) d_rec.extent(0) < atom->nmax) d_rec = decltype(d_rec)("contact:rec", atom->nmax);
  k.rec = d_rec;
  k.cur = rec_cur;
  fields_step();
  k.facc = d_facc;
  if (k.step.tool_particles && heat) {
    cross_build();
    k.xoff = d_xoff;
    k.xnb = d_xnb;
  }
  k.reset = reset_accum;
  near_build(k.step);
  k.near = d_near;
  const int nwork = nnear;
  k.dtlim = fixkk->dt_slot_view<DeviceType>(this);
  k.dtscale = dtfac * fixkk->courant();
  fixkk->k_dtlim.template sync<DeviceType>();
  // the sums go to d_sums on the device, the accumulators and the dt limit are updated there
  // (final): no host round trip; fetch() brings them to the host when an output needs them
  if (wide)
    sphcut::wide_reduce<DeviceType, 1>("sphcut:contact:post_force", nwork, ContactWide<DeviceType>{k}, d_wide_acc);
  else
    Kokkos::parallel_reduce("sphcut:contact:post_force", sphcut::range<DeviceType>(0, nwork), k,
                            Kokkos::subview(d_sums, (int) R_DTCRIT));
  reset_accum = 0;
  fixkk->k_dtlim.template modify<DeviceType>();
  fixkk->k_state.template modify<DeviceType>();
  k_qtw.template modify<DeviceType>();
  k_fout.template modify<DeviceType>();
  atomKK->modified(execution_space, F_MASK);
  stale = 1;
  records_stale = 1;
  rec_cur = 1 - rec_cur;
  if (k.step.tool_particles && heat) {
    sphcut::forward_comm(comm, this);
    tool_heat_gather();
  }
}

/* the host copies of the sums and totals (FixContactTriPenalty's members) from the device: the
   last step's sums, and the accumulated heat and work added to the totals.  Collective (all
   ranks call it at the same points: outputs, restart, end of run). */
template <class DeviceType> void FixContactTriPenaltyKokkos<DeviceType>::fetch()
{
  if (!stale) return;
  stale = 0;
  Kokkos::deep_copy(h_sums, d_sums);
  const double *r = h_sums.data(), *a = r + NRED;
  for (int d = 0; d < 3; d++) ftool[d] = r[R_FX + d];
  // work_rate and diss_rate (this step's rates alone) stay on the device, in the sums of the
  // trapezoid with the previous step's: only tool_work and contact_diss are used
  fric_power = r[R_FRIC];
  torque = r[R_TORQUE];
  ncontact = (int) r[C_NREC + 1 - rec_cur];    // the counter of the last evaluation
  dt_crit = r[R_DTCRIT];
  q_work += a[A_QWORK];
  q_tool_lost += a[A_QLOST];
  q_tool += a[A_QTOOL];
  tool_work += a[A_TWORK];
  contact_diss += a[A_DISS];
  if (tool_cp > 0.0) {
    double qsum = 0.0;
    MPI_Allreduce(&a[A_QLUMP], &qsum, 1, MPI_DOUBLE, MPI_SUM, world);
    tool_temp += qsum / tool_cp;
  }
  if (heat) heat->book_sources(a[A_QSRC]);
  reset_accum = 1;    // added to the totals: the next contact kernel zeroes them (final)
}

// what ContactKernel and CrossKernel sort particles by
template <class DeviceType> ContactMaskBits FixContactTriPenaltyKokkos<DeviceType>::mask_bits() const
{
  return {groupbit, toolbit, fix->toolbit, fix->clampbit, heat ? heat->groupbit : 0};
}

/* the cross neighbours (CrossKernel) from the lists of the last reneighbouring: once per build
   of the lists (and at each setup); the scan's total sizes d_xnb (grown, then scanned again)
   and the gather's range */
template <class DeviceType> void FixContactTriPenaltyKokkos<DeviceType>::cross_build()
{
  const int nlocal = atom->nlocal;
  if (xcalls == neighbor->ncalls && xnlocal == nlocal) return;
  xcalls = neighbor->ncalls;
  xnlocal = nlocal;
  if ((int) d_xoff.extent(0) < atom->nmax + 1) {
    d_xoff = Kokkos::View<int *, mem>("contact:xoff", atom->nmax + 1);
    d_xtool = Kokkos::View<int *, mem>("contact:xtool", atom->nmax);
  }
  if (d_xnb.extent(0) == 0) d_xnb = Kokkos::View<int *, mem>("contact:xnb", 1024);
  auto *kl = static_cast<NeighListKokkos<DeviceType> *>(list);
  CrossKernel<DeviceType> c;
  c.mask = atomKK->k_mask.view<DeviceType>();
  c.neighbors = kl->d_neighbors;
  c.numneigh = kl->d_numneigh;
  c.xoff = d_xoff;
  c.xtool = d_xtool;
  c.bits = mask_bits();
  int64_t total = 0;
  for (int pass = 0; pass < 2; pass++) {
    c.xnb = d_xnb;
    Kokkos::parallel_scan("sphcut:contact:cross_build", sphcut::range<DeviceType>(0, nlocal), c, total);
    const int64_t need = total & CrossKernel<DeviceType>::LOW;
    if (need <= (int64_t) d_xnb.extent(0)) break;
    d_xnb = Kokkos::View<int *, mem>("contact:xnb", need + need / 4 + 1024);
  }
  nxtool = nlocal > 0 ? (int) (total >> 32) : 0;
}

/* the contact kernel's particles (see the header; the bins' grid reaches one bin, at least the
   largest query radius, beyond the elements: tri_bin_build): a scan over the local particles, when the
   atoms may have moved in the arrays or beyond the slack (a setup, a reneighbouring, another
   number of particles) or the tool has moved more than half the slack since the last build.  The
   slack is twice the neighbour skin: a particle moves at most half the skin between two
   reneighbourings, the tool half the slack between two builds.                              */
template <class DeviceType> void FixContactTriPenaltyKokkos<DeviceType>::near_build(const sphcut::ContactStep &step)
{
  const int nlocal = atom->nlocal;
  const double near_slack = 2.0 * neighbor->skin;
  double moved2 = 0.0;
  for (int k = 0; k < 3; k++) moved2 += (step.disp[k] - near_disp[k]) * (step.disp[k] - near_disp[k]);
  // a rotating tool: a point of the grid's box moves by at most the turned angle times its
  // distance from the axis point (near_arm, the farthest corner of the widened box)
  const double moved = sqrt(moved2) + (step.rot.on ? fabs(theta - near_theta) * near_arm : 0.0);
  if (nnear >= 0 && !update->setupflag && near_calls == neighbor->ncalls && near_nlocal == nlocal &&
      moved <= 0.5 * near_slack)
    return;
  near_calls = neighbor->ncalls;
  near_nlocal = nlocal;
  for (int k = 0; k < 3; k++) near_disp[k] = step.disp[k];
  near_theta = theta;
  if ((int) d_near.extent(0) < atom->nmax) d_near = Kokkos::View<int *, mem>("contact:near", atom->nmax);
  NearKernel<DeviceType> c;
  c.x = atomKK->k_x.view<DeviceType>();
  c.mask = atomKK->k_mask.view<DeviceType>();
  c.qtw = k_qtw.template view<DeviceType>();
  c.fout = k_fout.template view<DeviceType>();
  c.near = d_near;
  c.bits = mask_bits();
  const sphcut::TriBinView &g = step.tool;
  c.ndim = g.nvert == 3 ? 3 : 2;
  for (int k = 0; k < 3; k++) {
    c.disp[k] = step.disp[k];
    c.lo[k] = g.lo[k] - near_slack;
    c.hi[k] = g.lo[k] + g.n[k] * g.size + near_slack;
  }
  c.none = g.nelem <= 0 || g.n[0] <= 0;
  c.rot = step.rot;
  near_arm = 0.0;
  for (int corner = 0; corner < 8; corner++) {
    double r2 = 0.0;
    for (int k = 0; k < c.ndim; k++) {
      const double e = ((corner >> k) & 1 ? c.hi[k] : c.lo[k]) - step.rot.p0[k];
      r2 += e * e;
    }
    near_arm = std::max(near_arm, sqrt(r2));
  }
  int total = 0;
  Kokkos::parallel_scan("sphcut:contact:near_build", sphcut::range<DeviceType>(0, nlocal), c, total);
  nnear = total;
}

/* the decomposition by tool feature (decomp) and the deepest penetration (maxpen) of the last
   contact evaluation, from its records when they are read: once per evaluation.  The records do
   not belong to atoms, so they stay valid when atoms move between ranks or are sorted, and
   between runs. */
template <class DeviceType> void FixContactTriPenaltyKokkos<DeviceType>::record_sums()
{
  if (!records_stale) return;
  fetch();    // ncontact: the number of records
  records_stale = 0;
  typedef RecordKernel<DeviceType> K;
  double res[K::NV];
  for (int v = 0; v < K::NV; v++) res[v] = 0.0;
  const int n = std::min(ncontact, (int) d_rec.extent(0));
  if (n > 0) {
    K k;
    k.rec = d_rec;
    Kokkos::View<double *, Kokkos::HostSpace, Kokkos::MemoryUnmanaged> r(res, K::NV);
    Kokkos::parallel_reduce("sphcut:contact:record_sums", sphcut::range<DeviceType>(0, n), k, r);
  }
  for (int ft = 0; ft < NFEAT; ft++)
    for (int c = 0; c < NDECOMP; c++) decomp[ft][c] = res[ft * NDECOMP + c];
  maxpen = res[K::V_MAXPEN];
}

template <class DeviceType> double FixContactTriPenaltyKokkos<DeviceType>::compute_vector(int n)
{
  fetch();
  if (n == 11 || n >= 15) record_sums();
  return FixContactTriPenalty::compute_vector(n);
}

template <class DeviceType> void FixContactTriPenaltyKokkos<DeviceType>::write_restart(FILE *fp)
{
  fetch();
  fields_fetch();
  FixContactTriPenalty::write_restart(fp);
}

/* the tool particles take the tool's share of the friction heat of the contact particles
   around them, kernel weighted (sphcut::ToolHeatGather; the CPU fix scatters it from the contact
   particle's side): as this fix's hook before the corrector in the corrector's kernel of fix
   sph/jc-thermal/kk of this step (or of the next step's first half, with the positions of the
   local particles from qtw; arm_hook) where this fix holds the hook (hooked), not at a setup (no
   corrector follows); else here, a kernel over the tool particles next to non-tool ones (the
   others have no contact particle around them), each over its non-tool neighbours in the list's
   order */
template <class DeviceType> void FixContactTriPenaltyKokkos<DeviceType>::tool_heat_gather()
{
  if (nxtool == 0) return;    // no tool particle has a non-tool neighbour (the tool is away)
  k_qtw.template sync<DeviceType>();
  sphcut::ToolHeatGather<DeviceType> g;
  g.active = 1;
  g.tb = toolbit;
  g.hb = heat->groupbit;
  g.kern = model->kernel();
  g.dim = domain->dimension;
  g.ntp = atom->ntypes + 1;
  g.use_rmass = atom->rmass_flag;
  g.acc = update->setupflag ? 0.0 : update->dt;
  g.av = sphcut::atom_views<DeviceType>(atomKK, fixkk->k_state);
  g.qtw = k_qtw.template view<DeviceType>();
  g.nlocal = atom->nlocal;
  g.xoff = d_xoff;
  g.xnb = d_xnb;
  g.mat = d_mat;
  g.hij = d_hij;
  g.qsrc = Kokkos::subview(d_sums, NRED + A_QSRC);
  fixkk->k_state.template modify<DeviceType>();
  if (hooked && !update->setupflag) {
    gather = g;
    gather_step = update->ntimestep;
    return;
  }
  auto xtool = d_xtool;
  Kokkos::parallel_for("sphcut:contact:tool_heat_gather", sphcut::range<DeviceType>(0, nxtool),
                       KOKKOS_LAMBDA(const int t) { g(xtool(t)); });
}

/* the hook before the corrector: the gather of the corrector's step, once (a reset_timestep cannot
   bring it back).  The integrator runs every step's corrector after that step's post_force */
template <class DeviceType>
void FixContactTriPenaltyKokkos<DeviceType>::arm_hook(sphcut::IntegratorHooks<DeviceType> &h, const sphcut::HookCall &c)
{
  if (c.pass != sphcut::HookCall::CORRECTOR || gather_step < 0 || gather_step != c.step) return;
  h.corrector.tool_heat = gather;
  gather_step = -1;
}

/* ---------------------------------------------------------------------- */

template <class DeviceType> void FixContactTriPenaltyKokkos<DeviceType>::end_of_step()
{
  compute_tool_velocity();
  if (toolbit && (vtool[0] != vtool_dev[0] || vtool[1] != vtool_dev[1] || vtool[2] != vtool_dev[2]))
    tool_velocity_device();
  fields_end_of_step();
  if (write_every && update->ntimestep % write_every == 0) write_geometry();
  // the per-atom contact force (f_ID) and the sums on the host on output steps and every
  // peratom_freq steps (the energy budget of fix heat/fmfs includes the friction heat then)
  if (update->ntimestep == output->next || update->ntimestep % peratom_freq == 0) {
    k_fout.sync_host();
    fetch();
  }
}

// between runs the per-atom output is on the host for any consumer
template <class DeviceType> void FixContactTriPenaltyKokkos<DeviceType>::post_run()
{
  k_fout.sync_host();
  fetch();
  fields_fetch();
  peratom_freq = 1;
}

/* the tool fields' facet tables to the device, and the host's running sums (a restart file's or
   the last run's) into d_facc */
template <class DeviceType> void FixContactTriPenaltyKokkos<DeviceType>::fields_upload()
{
  if (!fields.every) return;
  std::vector<int> se(fields.share_elem);
  se.push_back(0);    // never empty
  d_share_start = sphcut::to_device<int, DeviceType>(fields.share_start.data(), (int) fields.share_start.size(),
                                                     "contact:share_start");
  d_share_elem = sphcut::to_device<int, DeviceType>(se.data(), (int) se.size(), "contact:share_elem");
  d_inv_area = sphcut::to_device<double, DeviceType>(fields.inv_area.data(), fields.nfacet, "contact:inv_area");
  d_facc = sphcut::to_device<double, DeviceType>(fields.acc.data(), (int) fields.acc.size(), "contact:facc");
}

/* the running sums to the host (fields.acc) */
template <class DeviceType> void FixContactTriPenaltyKokkos<DeviceType>::fields_fetch()
{
  if (!fields.every || (int) d_facc.extent(0) != (int) fields.acc.size()) return;
  auto h = Kokkos::create_mirror_view(d_facc);
  Kokkos::deep_copy(h, d_facc);
  for (size_t k = 0; k < fields.acc.size(); k++) fields.acc[k] = h(k);
}

/* the interval's end: the sums to the host, averaged there (FixContactTriPenalty), then zeroed on
   the device: one copy per interval */
template <class DeviceType> void FixContactTriPenaltyKokkos<DeviceType>::fields_end_of_step()
{
  if (!fields.every || update->ntimestep % fields.every) return;
  fields_fetch();
  FixContactTriPenalty::fields_end_of_step();
  Kokkos::deep_copy(d_facc, 0.0);
}

// the rigid tool particles move with the tool
template <class DeviceType> void FixContactTriPenaltyKokkos<DeviceType>::tool_velocity_device()
{
  atomKK->sync(execution_space, V_MASK | MASK_MASK);
  auto v = atomKK->k_v.view<DeviceType>();
  auto mask = atomKK->k_mask.view<DeviceType>();
  const int tb = toolbit;
  const double v0 = vtool[0], v1 = vtool[1], v2 = vtool[2];
  for (int d = 0; d < 3; d++) vtool_dev[d] = vtool[d];
  Kokkos::parallel_for("sphcut:contact:tool_velocity_device",
      sphcut::range<DeviceType>(0, atom->nlocal), KOKKOS_LAMBDA(const int i) {
        if (!(mask(i) & tb)) return;
        v(i, 0) = v0;
        v(i, 1) = v1;
        v(i, 2) = v2;
      });
  atomKK->modified(execution_space, V_MASK);
}

/* ---------------------------------------------------------------------- */

template <class DeviceType>
int FixContactTriPenaltyKokkos<DeviceType>::SPHCUT_KK_FIX_PACK_FORWARD(int n, SPHCUT_KK_SENDLIST(k_sendlist, iswap),
    sphcut::kk_buf &k_buf, int, int *)
{
  return sphcut::pack_columns<DeviceType>(k_qtw, 0, 1, n, k_sendlist, SPHCUT_KK_ISWAP(iswap), k_buf);
}

template <class DeviceType>
void FixContactTriPenaltyKokkos<DeviceType>::SPHCUT_KK_FIX_UNPACK_FORWARD(int n, int first, sphcut::kk_buf &k_buf)
{
  sphcut::unpack_columns<DeviceType>(k_qtw, 0, 1, n, first, k_buf);
}

template <class DeviceType>
int FixContactTriPenaltyKokkos<DeviceType>::pack_forward_comm(int n, int *list_, double *buf, int, int *)
{
  return stage_qtw.pack(k_qtw, 0, 1, n, list_, buf);
}

template <class DeviceType> void FixContactTriPenaltyKokkos<DeviceType>::unpack_forward_comm(int n, int first, double *buf)
{
  stage_qtw.unpack(k_qtw, 0, 1, n, first, buf);
}

namespace LAMMPS_NS {
template class FixContactTriPenaltyKokkos<LMPDeviceType>;
#ifdef LMP_KOKKOS_GPU
template class FixContactTriPenaltyKokkos<LMPHostType>;
#endif
}    // namespace LAMMPS_NS
