/* ----------------------------------------------------------------------
   sphcut - fix heat/fmfs/kk

   One evaluation on the device (every N steps, as the CPU fix):
     conservative (default)  kernel 1: per particle the scheme (FMFS or
                             Brookshaw) and the FMFS pair weights; device
                             forward communication of the weights; kernel 2:
                             the pairwise exchange and the surface losses
                             into the held rate (state column HELD)
     conservative no         one kernel: the FMFS or Brookshaw Laplacian
   Other steps launch nothing here: this fix's hooks run in the kernels of
   fix sph/jc-thermal/kk (sphcut_heat_hooks_kokkos.h, handed over in init
   through sphcut::HookHost::set_hook, filled by arm_hooks): after its
   first half the predicted temperature of the Dirichlet groups; before
   its corrector the held rate into the temperature rate DTEMP; right
   after it the Dirichlet particles back to their temperature, the heat
   that takes (the heat through the clamp) summed into this fix's device
   accumulator k_qdir, read when it needs q_dirichlet (output, restart,
   end of run), and with an adaptive step the thermal dt limit into this
   fix's own dt slot, on the device.  At the setup this fix sets the
   Dirichlet temperatures and adds the held rate in a kernel each.  The
   few global sums of an evaluation (loss rates, scheme counters) come
   back by parallel_reduce.
------------------------------------------------------------------------- */

#include "fix_heat_fmfs_kokkos.h"

#include "atom_kokkos.h"
#include "atom_masks.h"
#include "comm.h"
#include "compute_surface_lambda_kokkos.h"
#include "domain.h"
#include "error.h"
#include "fix_sph_jc_thermal_kokkos.h"
#include "modify.h"
#include "neigh_list_kokkos.h"
#include "neighbor.h"
#include "sphcut_model.h"
#include "update.h"

#include "sphcut_compat.h"
#include "sphcut_kernels.h"
#include "sphcut_kokkos.h"
#include "sphcut_thermal.h"

#include <cstring>
#include <vector>

using namespace LAMMPS_NS;
using namespace FixConst;

namespace {
// k_fwts: a pad, then the NW communicated columns: the scheme flag (FW0) and the FMFS weights,
// Gf (3x3) and z (3), 16-byte aligned for sphcut::load_weights
// (enumerators: constants a device lambda may take by reference)
enum FmfsColumns : int { NW = 1 + 3 * 3 + 3, FW0 = 1, NWCOL = FW0 + NW };
// rows of 16-byte multiples, so that each row's weights (column FW0 + 1) are 16-byte aligned
static_assert(NWCOL % 2 == 0 && (FW0 + 1) % 2 == 0, "FMFS weights not 16-byte aligned");
// a particle's heat row (build_heat_rows, local + ghost, per evaluation): what its neighbours
// read of it, in 16-byte pairs (sphcut::load2): position, type (0: not in the fix's group),
// volume m/rho of the predicted density, predicted temperature; 2 sectors of 32 bytes
// instead of pieces of x, mask, type, mass and the 49-column state row
enum HeatRow { HR_X = 0, HR_TYPE = 3, HR_VOL = 4, HR_T = 5, NHR = 6 };
static_assert(NHR % 2 == 0, "heat rows not 16-byte multiples");

// a pass's reduction of N sums whose final, once after every particle, updates the losses on the
// device (FixHeatFMFSKokkos::d_loss): body(ii, r) per list entry, fin(r, N) at the end
template <class DeviceType, int N, class Body, class Fin> struct FinalSums {
  typedef DeviceType device_type;
  typedef double value_type[];
  const unsigned value_count = N;
  Body body;
  Fin fin;
  FinalSums(const Body &b, const Fin &f) : body(b), fin(f) {}
  KOKKOS_INLINE_FUNCTION void init(value_type r) const
  {
    for (int k = 0; k < N; k++) r[k] = 0.0;
  }
  KOKKOS_INLINE_FUNCTION void join(SPHCUT_KK_VOLATILE value_type d, const SPHCUT_KK_VOLATILE value_type s) const
  {
    for (int k = 0; k < N; k++) d[k] += s[k];
  }
  KOKKOS_INLINE_FUNCTION void operator()(const int ii, value_type r) const { body(ii, r); }
  KOKKOS_INLINE_FUNCTION void final(value_type r) const { fin(r, N); }
  KOKKOS_INLINE_FUNCTION static constexpr bool is_min(int) { return false; }    // (sphcut::reduce)
};
template <class DeviceType, int N, class Body, class Fin> FinalSums<DeviceType, N, Body, Fin> final_sums(Body b, Fin f)
{
  return FinalSums<DeviceType, N, Body, Fin>(b, f);
}

// a pass's final on the losses (FixHeatFMFSKokkos::d_loss): with rates, the rates it replaces
// take their weight wr into the convective and radiative heat and its sums r[0], r[1] become the
// rates; with c0 >= 0 its sums r[c0 ..] add to the three scheme counters (n: the pass's sums, which
// hold them)
template <class DeviceType> struct LossFinal {
  typedef FixHeatFMFSKokkos<DeviceType> F;
  static_assert(F::L_NBROOK == F::L_NFMFS + 1 && F::L_NFALL == F::L_NFMFS + 2, "scheme counters not contiguous");
  Kokkos::View<double *, typename DeviceType::memory_space> loss;
  double wr;
  int rates, c0;
  KOKKOS_INLINE_FUNCTION void operator()(const double *r, int n) const
  {
    if (rates) {
      loss(F::L_QCONV) += wr * loss(F::L_CONV);
      loss(F::L_QRAD) += wr * loss(F::L_RAD);
      loss(F::L_CONV) = r[0];
      loss(F::L_RAD) = r[1];
    }
    if (c0 >= 0 && c0 + 3 <= n)
      for (int k = 0; k < 3; k++) loss(F::L_NFMFS + k) += r[c0 + k];
  }
};
}    // namespace

template <class DeviceType>
FixHeatFMFSKokkos<DeviceType>::FixHeatFMFSKokkos(LAMMPS *lmp, int narg, char **arg) :
    FixHeatFMFS(sphcut::require_kokkos(lmp, "Fix heat/fmfs/kk"), narg, arg), fixkk(nullptr), surfkk(nullptr)
{
  kokkosable = 1;
  forward_comm_device = 1;
  atomKK = (AtomKokkos *) atom;
  execution_space = ExecutionSpaceFromDevice<DeviceType>::space;
  datamask_read = X_MASK | MASK_MASK | TYPE_MASK | RMASS_MASK;
  datamask_modify = EMPTY_MASK;
  k_qdir = DAT::tdual_double_1d("heat/fmfs:qdir", 1);
  k_qdir.view_host()(0) = 0.0;
  k_qdir.modify_host();
  k_qdir.template sync<DeviceType>();
}

template <class DeviceType> FixHeatFMFSKokkos<DeviceType>::~FixHeatFMFSKokkos() {}

// restart files match fixes by ID and style: the /kk fix goes by the CPU style's name (as the
// mechanics fix does), so the energy budget continues under either
template <class DeviceType> void FixHeatFMFSKokkos<DeviceType>::post_constructor()
{
  delete[] style;
  style = utils::strdup("heat/fmfs");
}

template <class DeviceType> void FixHeatFMFSKokkos<DeviceType>::init()
{
  FixHeatFMFS::init();
  sphcut::kokkos_full_list<DeviceType>(neighbor);
  wide = sphcut::wide_choice<DeviceType>(lmp, "Fix heat/fmfs/kk");
  eager = sphcut::load_ahead<DeviceType>(lmp, "Fix heat/fmfs/kk");
  fixkk = dynamic_cast<FixSPHJCThermalKokkosBase *>(fix);
  if (!fixkk) error->all(FLERR, "Fix heat/fmfs/kk requires fix sph/jc-thermal/kk (run with -sf kk)");
  surfkk = nullptr;
  if (surface) {
    surfkk = dynamic_cast<ComputeSurfaceLambdaKokkosBase *>(surface);
    if (!surfkk)
      error->all(FLERR, "Fix heat/fmfs/kk: surface compute {} is not compute surface/lambda/kk (run with -sf kk)",
                 id_surface);
  }
  const int n = atom->ntypes + 1;
  d_mat = sphcut::to_device<sphcut::Material, DeviceType>(model->materials(), n, "heat/fmfs:mat");
  std::vector<double> h(n, 0.0);
  for (int i = 1; i < n; i++) h[i] = model->smoothing_length(i);
  d_hij = sphcut::to_device<double, DeviceType>(hij.data(), n * n, "heat/fmfs:hij");
  d_h = sphcut::to_device<double, DeviceType>(h.data(), n, "heat/fmfs:h");
  d_tp = sphcut::to_device<sphcut::ThermalPair, DeviceType>(tpair.data(), (int) tpair.size(), "heat/fmfs:tp");
  sphcut::dirichlet_to_device<DeviceType>(dir_bits, dir_temps, "heat/fmfs", d_dirbit, d_dirtemp);
  // the rules and the thermal limit as hooks in the integrator's kernels (no kernel here on a step
  // without an evaluation)
  slot_step = -1;
  const sphcut::HookArm<DeviceType> arm = [this](sphcut::IntegratorHooks<DeviceType> &h,
                                                 const sphcut::HookCall &c) { arm_hooks(h, c); };
  if (!fixkk->set_hook<DeviceType>(this, sphcut::HOOK_HEAT, arm))
    error->all(FLERR, "Fix heat/fmfs/kk: fix {} runs on another Kokkos device type; use the same "
               "variant (/kk, /kk/device or /kk/host) for both", fix->id);
}

/* this fix's hooks for a pass of fix sph/jc-thermal/kk (sphcut_heat_hooks_kokkos.h): after the
   first half the Dirichlet groups' predicted temperature; before and after the corrector the held
   rate, the Dirichlet groups with their heat into k_qdir, and on a step whose dt limits the host
   reads the thermal limit into this fix's slot (slot_step, slot_F: when it was written) */
template <class DeviceType>
void FixHeatFMFSKokkos<DeviceType>::arm_hooks(sphcut::IntegratorHooks<DeviceType> &h, const sphcut::HookCall &c)
{
  const int nd = (int) dir_bits.size();
  sphcut::HeatRulesView<DeviceType> rules;
  rules.gb = groupbit;
  rules.nd = nd;
  rules.dbit = d_dirbit;
  rules.dtemp = d_dirtemp;
  if (c.pass == sphcut::HookCall::FIRST_HALF) {
    auto &p = h.first_half.heat;
    p.active = nd > 0;
    p.rules = rules;
    return;
  }
  auto &k = h.corrector.heat;
  k.active = 1;
  k.rules = rules;
  k.h = d_h;
  k.every = every;
  k.F = fixkk->thermal_courant();
  k.want_lim = c.want_dt && fixkk->holds_slot(this);
  if (k.want_lim) {
    k.slot = fixkk->dt_slot_view<DeviceType>(this);    // (k_dtlim: synced and marked by the integrator)
    slot_step = c.step;
    slot_F = k.F;
  }
  if (nd) {
    k_qdir.template sync<DeviceType>();
    k_qdir.template modify<DeviceType>();    // (the kernel follows)
    qdir_pending = 1;
  }
  k.qacc = k_qdir.template view<DeviceType>();
}

/* thermal time step limit of this rank: in this fix's slot when its hook after the corrector of
   fix sph/jc-thermal/kk wrote it this step (that fix reads the slot with the others at its
   end_of_step), else (setup, another Courant number) a reduction on the device here */
template <class DeviceType> int FixHeatFMFSKokkos<DeviceType>::dt_limit_on_device() const
{
  return fixkk && slot_step >= 0 && slot_step == update->ntimestep && !update->setupflag;
}

template <class DeviceType> double FixHeatFMFSKokkos<DeviceType>::dt_limit(double, double Fc) const
{
  if (!fixkk || d_mat.extent(0) == 0) return 1.0e300;
  if (dt_limit_on_device() && slot_F == Fc) return 1.0e300;
  fixkk->k_state.template sync<DeviceType>();
  auto st = fixkk->k_state.template view<DeviceType>();
  auto mask = atomKK->k_mask.view<DeviceType>();
  auto type = atomKK->k_type.view<DeviceType>();
  auto mat = d_mat;
  auto h = d_h;
  const int gb = groupbit, ev = every;
  double dt = 1.0e300;
  Kokkos::parallel_reduce("sphcut:heat:dt_limit",
      sphcut::range<DeviceType>(0, atom->nlocal),
      KOKKOS_LAMBDA(const int i, double &m) {
        if (!(mask(i) & gb)) return;
        const int t = type(i);
        sphcut::thermal_dt_min(mask(i), gb, st(i, FixSPHJCThermal::RHO), mat(t).cp, mat(t).kappa, h(t), Fc, ev, m);
      },
      Kokkos::Min<double>(dt));
  return dt;
}

template <class DeviceType> void FixHeatFMFSKokkos<DeviceType>::setup(int vflag)
{
  check_timestep();
  push_losses();
  if (!dir_bits.empty()) {
    set_dirichlet();    // Dirichlet particles start at their temperature
    sphcut::forward_comm(comm, fix);
  }
  post_force(vflag);
}

/* ---------------------------------------------------------------------- */

template <class DeviceType> void FixHeatFMFSKokkos<DeviceType>::post_force(int)
{
  // an evaluation step computes the held rate HELD; this fix's hook in the corrector of fix
  // sph/jc-thermal/kk adds it to the temperature rate (sphcut::add_held_rate), so other steps launch
  // nothing here
  const int eval = every == 1 || update->setupflag || update->ntimestep % every == 0;
  // the trapezoid of the losses over the step (FixHeatFMFS::post_force: dt/2 of the last step's
  // rates and dt/2 of this one's), kept as weights: an evaluation's final adds the rates it
  // replaces times their weight (this step's half included) to the device's sums
  const double hdt = update->setupflag ? 0.0 : 0.5 * update->dt;
  if (eval) {
    replaced_weight = loss_weight + hdt;
    loss_weight = hdt;
    losses_stale = 1;
  } else {
    loss_weight += 2.0 * hdt;
  }
  if (eval) {
    begin_evaluation();
    sphcut::FencedTimer timer(cpu_time);
    atomKK->sync(execution_space, datamask_read);
    fixkk->k_state.template sync<DeviceType>();
    build_heat_rows();
    if (conservative) {
      if (domain->dimension == 2) conduction_conservative_kk<2>();
      else conduction_conservative_kk<3>();
    } else {
      if (domain->dimension == 2) conduction_kk<2>();
      else conduction_kk<3>();
    }
    if (update->setupflag) add_held();    // (no corrector follows the setup)
  }
}

// the host's budget, rates and counters to the device (the setup: restart files, earlier runs)
template <class DeviceType> void FixHeatFMFSKokkos<DeviceType>::push_losses()
{
  if ((int) d_loss.extent(0) != NLOSS) {
    d_loss = Kokkos::View<double *, typename DeviceType::memory_space>("heat/fmfs:loss", NLOSS);
    d_red = Kokkos::View<double *, typename DeviceType::memory_space>("heat/fmfs:red", NLOSS);
  }
  auto h = Kokkos::create_mirror_view(d_loss);
  h(L_CONV) = held_conv;
  h(L_RAD) = held_rad;
  h(L_QCONV) = q_conv;
  h(L_QRAD) = q_rad;
  h(L_NFMFS) = h(L_NBROOK) = h(L_NFALL) = 0.0;
  Kokkos::deep_copy(d_loss, h);
  for (int k = 0; k < NLOSS; k++) loss_host[k] = h(k);
  count_base[0] = n_fmfs;
  count_base[1] = n_brookshaw;
  count_base[2] = n_fallback;
  loss_weight = 0.0;
  losses_stale = 0;
}

// the host's budget, rates and counters from the device (copied only when an evaluation ran
// since): the sums of the replaced rates plus the current rates times the time they have acted for
template <class DeviceType> void FixHeatFMFSKokkos<DeviceType>::fetch_losses()
{
  if ((int) d_loss.extent(0) != NLOSS) return;    // (no run yet)
  if (losses_stale) {
    auto h = Kokkos::create_mirror_view(d_loss);
    Kokkos::deep_copy(h, d_loss);
    for (int k = 0; k < NLOSS; k++) loss_host[k] = h(k);
    losses_stale = 0;
  }
  const double *h = loss_host;
  held_conv = h[L_CONV];
  held_rad = h[L_RAD];
  q_conv = h[L_QCONV] + loss_weight * h[L_CONV];
  q_rad = h[L_QRAD] + loss_weight * h[L_RAD];
  n_fmfs = count_base[0] + (bigint) h[L_NFMFS];
  n_brookshaw = count_base[1] + (bigint) h[L_NBROOK];
  n_fallback = count_base[2] + (bigint) h[L_NFALL];
}

// FixHeatFMFS::begin_evaluation with the compute's values on the device
template <class DeviceType> bool FixHeatFMFSKokkos<DeviceType>::begin_evaluation()
{
  fuse_surface = false;
  if (!surfkk || surfkk->invoked_peratom == update->ntimestep) return false;
  if (conservative && surfkk->fusable(groupbit)) fuse_surface = surfkk->begin_step();
  else surfkk->compute_device();
  return fuse_surface;
}

// the held rate into the temperature rate at the setup (FixHeatFMFS::post_force)
template <class DeviceType> void FixHeatFMFSKokkos<DeviceType>::add_held()
{
  auto st = fixkk->k_state.template view<DeviceType>();
  auto mask = atomKK->k_mask.view<DeviceType>();
  const int gb = groupbit;
  Kokkos::parallel_for("sphcut:heat:add_held",
      sphcut::range<DeviceType>(0, atom->nlocal), KOKKOS_LAMBDA(const int i) {
        if (mask(i) & gb) sphcut::add_held_rate(&st(i, 0));
      });
  fixkk->k_state.template modify<DeviceType>();
}

// what the heat kernels read on the device (captured by value)
template <class DeviceType> struct LAMMPS_NS::HeatFMFSViews {
  typedef typename DeviceType::memory_space mem;
  sphcut::AtomViews<DeviceType> av;
  Kokkos::View<const sphcut::Material *, mem> mat;
  Kokkos::View<const double *, mem> hij;
  Kokkos::View<const sphcut::ThermalPair *, mem> tp;
  typename ArrayTypes<DeviceType>::t_double_2d fw, hr;
  int nt, kern, gb, use_rmass;
};

namespace {

// the listed neighbours of particle i as the sphcut_thermal.h particle functions read them, from
// the heat rows: the pair's support and kernel computed on the fly (one walk).  EAGER (the
// conservative form's passes on a GPU, FixHeatFMFSKokkos::eager): the walk takes the entries in
// order (pair(0), pair(1), ...), each entry's index is loaded one entry ahead, and pair() loads
// what the pass then reads of j before the support test: its whole heat row (EAGER >= 1) and its
// scheme flag (EAGER == 2, the exchange), so that these loads wait for the index only, not for the
// test and then for each other; the FMFS weights follow the test, for the pairs within the support
// only (loaded before it as well, the exchange was slower: bench/gpu/RESULTS.md).  The values and
// the sums are the same.  EAGER == 0 loads each where it is read.
template <class DeviceType, int DIM = 3, int EAGER = 0> struct DeviceNeighbours {
  static constexpr bool TWO_WALKS = false;
  const HeatFMFSViews<DeviceType> &d;
  int i, itn;    // itn: the row of i's type in the type-pair tables
  double xi[3];
  // EAGER: the last pair's j as pair() loaded it, the next entry's index
  mutable double cvol, ctemp;
  mutable bool cflag;
  mutable int jnext;
  KOKKOS_INLINE_FUNCTION DeviceNeighbours(const HeatFMFSViews<DeviceType> &d_, int i_) :
      d(d_), i(i_), itn(d_.av.type(i_) * d_.nt), xi{d_.hr(i_, HR_X), d_.hr(i_, HR_X + 1), d_.hr(i_, HR_X + 2)}
  {
    if (EAGER) jnext = d.av.numneigh(i) > 0 ? d.av.neighbors(i, 0) & NEIGHMASK : 0;
  }
  KOKKOS_INLINE_FUNCTION int size() const { return d.av.numneigh(i); }
  KOKKOS_INLINE_FUNCTION int type(int j) const { return (int) d.hr(j, HR_TYPE); }
  // the position and type of j (type 0: not in the group)
  KOKKOS_INLINE_FUNCTION int pos_type(int j, double *xj) const
  {
    double t;
    sphcut::load2(&d.hr(j, HR_X), xj[0], xj[1]);
    sphcut::load2(&d.hr(j, HR_X + 2), xj[2], t);
    return (int) t;
  }
  KOKKOS_INLINE_FUNCTION int index(int k) const
  {
    const int j = d.av.neighbors(i, k) & NEIGHMASK;
    return type(j) > 0 ? j : -1;
  }
  KOKKOS_INLINE_FUNCTION void pos(int j, double *xj) const { pos_type(j, xj); }
  KOKKOS_INLINE_FUNCTION double h(int j) const { return d.hij(itn + type(j)); }
  KOKKOS_INLINE_FUNCTION bool pair(int k, sphcut::HeatPair &p) const
  {
    if (EAGER) {
      p.j = jnext;
      if (k + 1 < d.av.numneigh(i)) jnext = d.av.neighbors(i, k + 1) & NEIGHMASK;
    } else {
      p.j = d.av.neighbors(i, k) & NEIGHMASK;
    }
    double xj[3], r2;
    const int tj = pos_type(p.j, xj);
    if (EAGER) {
      sphcut::load2(&d.hr(p.j, HR_VOL), cvol, ctemp);
      if (EAGER == 2) {
        double pad, flag;
        sphcut::load2(&d.fw(p.j, FW0 - 1), pad, flag);
        cflag = flag > 0.0;
      }
    }
    if (tj == 0) return false;
    p.tp = &d.tp(itn + tj);
    return sphcut::thermal_support(*p.tp, d.kern, xi, xj, p.dx, r2, p.wfac, p.ir2);
  }
  KOKKOS_INLINE_FUNCTION double volume(int j) const { return EAGER ? cvol : d.hr(j, HR_VOL); }
  KOKKOS_INLINE_FUNCTION double temp(int j) const { return EAGER ? ctemp : d.hr(j, HR_T); }
  template <int D> KOKKOS_INLINE_FUNCTION bool weights(int j, double *w) const
  {
    static_assert(D == DIM, "the weights of another dimension");
    if (EAGER < 2) return sphcut::row_weights<D>(&d.fw(j, FW0), w);
    if (cflag) sphcut::load_weights<D>(&d.fw(j, FW0 + 1), w);
    return cflag;
  }
  KOKKOS_INLINE_FUNCTION double kappa(int j) const { return d.mat(type(j)).kappa; }
};
}    // namespace

template <class DeviceType> HeatFMFSViews<DeviceType> FixHeatFMFSKokkos<DeviceType>::heat_views()
{
  HeatFMFSViews<DeviceType> d;
  d.av = sphcut::atom_views<DeviceType>(atomKK, fixkk->k_state, list);
  d.mat = d_mat;
  d.hij = d_hij;
  d.tp = d_tp;
  d.fw = k_fwts.template view<DeviceType>();
  d.hr = d_hrow;
  d.nt = atom->ntypes + 1;
  d.kern = model->kernel();
  d.gb = groupbit;
  d.use_rmass = atom->rmass_flag;
  return d;
}

/* the heat rows of the local and ghost particles (HeatRow), from the values the neighbour
   passes read: the same values, one contiguous row per particle */
template <class DeviceType> void FixHeatFMFSKokkos<DeviceType>::build_heat_rows()
{
  using F = FixSPHJCThermal;
  const int nall = atom->nlocal + atom->nghost;
  if ((int) d_hrow.extent(0) < atom->nmax) {
    d_hrow = typename AT::t_double_2d("heat/fmfs:hrow", atom->nmax, NHR);
    sphcut::require_aligned16(lmp, d_hrow.data(), "Fix heat/fmfs/kk: the heat rows");
  }
  const auto av = sphcut::atom_views<DeviceType>(atomKK, fixkk->k_state);
  auto hr = d_hrow;
  const int gb = groupbit, use_rmass = atom->rmass_flag;
  Kokkos::parallel_for("sphcut:heat:rows", sphcut::range<DeviceType>(0, nall), KOKKOS_LAMBDA(const int i) {
    for (int a = 0; a < 3; a++) hr(i, HR_X + a) = av.x(i, a);
    const int in = av.mask(i) & gb;
    hr(i, HR_TYPE) = in ? av.type(i) : 0;
    hr(i, HR_VOL) = in ? (use_rmass ? av.rmass(i) : av.mass(av.type(i))) / av.st(i, F::RHO_F) : 0.0;
    hr(i, HR_T) = av.st(i, F::TEMP_F);
  });
}

/* the non-conservative form (FixHeatFMFS::conduction): sphcut::conduction_particle per particle */
template <class DeviceType> template <int DIM> void FixHeatFMFSKokkos<DeviceType>::conduction_kk()
{
  using F = FixSPHJCThermal;
  const HeatFMFSViews<DeviceType> d = heat_views();
  const auto &av = d.av;
  typename AT::t_double_2d surf;
  if (surfkk) surf = surfkk->k_out.template view<DeviceType>();
  auto mat = d_mat;
  const int gb = groupbit, use_rmass = atom->rmass_flag, kern = d.kern;
  const int has_surf = surfkk != nullptr, fmfs = scheme == FMFS;
  const double flam = fmfs_lambda;
  const sphcut::HeatLosses hl = losses();
  const LossFinal<DeviceType> fin{d_loss, replaced_weight, 1, 2};

  Kokkos::parallel_for("sphcut:heat:zero_held_pp",
      sphcut::range<DeviceType>(0, atom->nlocal), KOKKOS_LAMBDA(const int i) { av.st(i, F::HELD) = 0.0; });
  // (sums: the convective and radiative loss rates, the three scheme counters)
  sphcut::reduce<DeviceType, 5>("sphcut:heat:per_particle", list->inum,
      final_sums<DeviceType, 5>(KOKKOS_LAMBDA(const int ii, double *r) {
        double &p_conv = r[0], &p_rad = r[1], &c_fmfs = r[2], &c_brook = r[3], &c_fall = r[4];
        const int i = d.av.ilist(ii);
        if (!(d.av.mask(i) & gb)) return;
        const int itype = d.av.type(i);
        const sphcut::Material &mi = mat(itype);
        if (mi.cp <= 0.0) return;
        const double Ti = d.av.st(i, F::TEMP_F);
        const int is_surf = has_surf ? surf(i, ComputeSurfaceLambda::FLAG) > 0.5 : 0;
        const DeviceNeighbours<DeviceType> nbr(d, i);
        double rate;
        const int s = sphcut::conduction_particle<DIM>(nbr, kern, nbr.xi, Ti, mi.kappa, fmfs && !is_surf && mi.kappa > 0.0,
                                                       flam, rate);
        sphcut::heat_count(s, c_fmfs, c_brook, c_fall);
        d.av.st(i, F::HELD) = sphcut::heat_rate(DIM, hl, is_surf, d.av.mask(i), rate, d.av.st(i, F::RHO_F),
                                                use_rmass ? d.av.rmass(i) : d.av.mass(itype), mi.cp, Ti, p_conv, p_rad);
      }, fin),
      wide,
      Kokkos::subview(d_red, std::make_pair(0, 5)), d_wide_acc);
  fixkk->k_state.template modify<DeviceType>();
}

/* the conservative form (FixHeatFMFS::conduction_conservative): the scheme pass, the device
   forward communication of the weights, the exchange pass */
template <class DeviceType> template <int DIM> void FixHeatFMFSKokkos<DeviceType>::conduction_conservative_kk()
{
  if ((int) k_fwts.extent(0) < atom->nmax) {
    k_fwts = DAT::tdual_double_2d("heat/fmfs:fwts", atom->nmax, NWCOL);
    sphcut::require_aligned16(lmp, k_fwts.template view<DeviceType>().data(), "Fix heat/fmfs/kk: the FMFS weights");
  }
  k_fwts.template sync<DeviceType>();
  typename AT::t_double_2d surf;
  if (surfkk) {
    surfkk->k_out.template sync<DeviceType>();
    surf = surfkk->k_out.template view<DeviceType>();
  }
  const HeatFMFSViews<DeviceType> d = heat_views();
  if (eager)
    scheme_pass_kk<DIM, 1>(d, surf);
  else
    scheme_pass_kk<DIM, 0>(d, surf);
  sphcut::forward_comm(comm, this);
  k_fwts.template sync<DeviceType>();
  if (eager)
    exchange_pass_kk<DIM, 2>(d, surf);
  else
    exchange_pass_kk<DIM, 0>(d, surf);
}

/* 1. one thread per particle walks its neighbours once for the surface indicator (fused: into
   the compute's values) and the FMFS moments (sphcut::heat_scheme), the same sums in the same
   order as the CPU fix: the scheme of each particle and its FMFS pair weights */
template <class DeviceType>
template <int DIM, int EAGER>
void FixHeatFMFSKokkos<DeviceType>::scheme_pass_kk(const HeatFMFSViews<DeviceType> &d,
                                                   const typename AT::t_double_2d &surf)
{
  using CS = ComputeSurfaceLambda;
  auto fw = d.fw;
  auto mat = d_mat;
  const int gb = groupbit, has_surf = surfkk != nullptr, fmfs = scheme == FMFS, fuse = fuse_surface;
  const double flam = fmfs_lambda, thr = surfkk ? surfkk->threshold : 0.0;
  const LossFinal<DeviceType> fin{d_loss, 0.0, 0, 0};
  // every local particle's weight flag and surface values are cleared before they are set: in
  // the pass itself when its list holds every local particle (the ghosts take theirs from the
  // forward communication after it), else in kernels of their own first
  const int clear = list->inum == atom->nlocal;
  if (!clear) {
    Kokkos::parallel_for("sphcut:heat:zero_weights",
        sphcut::range<DeviceType>(0, atom->nlocal + atom->nghost), KOKKOS_LAMBDA(const int i) { fw(i, FW0) = 0.0; });
    if (fuse)
      Kokkos::parallel_for(
          "sphcut:heat:zero_surface", sphcut::range<DeviceType>(0, atom->nlocal), KOKKOS_LAMBDA(const int i) {
            for (int k = 0; k < CS::NCOLS; k++) surf(i, k) = 0.0;
          });
  }
  // (sums: the three scheme counters)
  const auto pass = final_sums<DeviceType, 3>(KOKKOS_LAMBDA(const int ii, double *r) {
        double &c_fmfs = r[0], &c_brook = r[1], &c_fall = r[2];
        const int i = d.av.ilist(ii);
        if (clear) {
          fw(i, FW0) = 0.0;
          if (fuse)
            for (int k = 0; k < CS::NCOLS; k++) surf(i, k) = 0.0;
        }
        if (!(d.av.mask(i) & gb)) return;
        const sphcut::Material &mi = mat(d.av.type(i));
        const int conducts = mi.cp > 0.0;
        const int was_surf = !fuse && has_surf && surf(i, CS::FLAG) > 0.5;
        const int cand = conducts && fmfs && mi.kappa > 0.0 && !was_surf;
        sphcut::HeatSurface sv;
        double wts[NW - 1];
        const int s = sphcut::heat_scheme<DIM>(DeviceNeighbours<DeviceType, DIM, EAGER>(d, i), conducts, cand, fuse, thr, flam, sv, wts);
        if (fuse) {
          surf(i, CS::LAMBDA) = sv.lambda;
          surf(i, CS::FLAG) = sv.flag;
          for (int a = 0; a < DIM; a++) surf(i, CS::NX + a) = sv.n[a];
        }
        if (s == sphcut::HEAT_FMFS) {
          for (int k = 0; k < NW - 1; k++) fw(i, FW0 + 1 + k) = wts[k];
          fw(i, FW0) = 1.0;
        }
        sphcut::heat_count(s, c_fmfs, c_brook, c_fall);
      }, fin);
  // compiled with launch bounds of 128 threads a block, 3 blocks a multiprocessor: 168 registers in
  // 3D, no spill (174 without; bench/gpu/RESULTS.md "Launch bounds"; 4 blocks: 128 registers,
  // 784 bytes of spill)
  sphcut::reduce<DeviceType, 3, 3>("sphcut:heat:weights", list->inum, pass,
                                   wide,
                                   Kokkos::subview(d_red, std::make_pair(0, 3)), d_wide_acc);
  k_fwts.template modify<DeviceType>();
  if (fuse) surfkk->k_out.template modify<DeviceType>();
}

/* 2. the pairwise exchange (sphcut::heat_exchange, each pair from both sides: nothing to
   scatter) and the surface losses into the held rate */
template <class DeviceType>
template <int DIM, int EAGER>
void FixHeatFMFSKokkos<DeviceType>::exchange_pass_kk(const HeatFMFSViews<DeviceType> &d,
                                                     const typename AT::t_double_2d &surf)
{
  using F = FixSPHJCThermal;
  const auto &av = d.av;
  auto fw = d.fw;
  auto mat = d_mat;
  const int gb = groupbit, use_rmass = atom->rmass_flag, has_surf = surfkk != nullptr;
  const sphcut::HeatLosses hl = losses();
  const LossFinal<DeviceType> fin{d_loss, replaced_weight, 1, -1};
  // the held rate of every local particle is set: by the pass itself when its list holds every
  // local particle, else cleared first in a kernel of its own
  const int clear = list->inum == atom->nlocal;
  if (!clear)
    Kokkos::parallel_for("sphcut:heat:zero_held",
        sphcut::range<DeviceType>(0, atom->nlocal), KOKKOS_LAMBDA(const int i) { av.st(i, F::HELD) = 0.0; });
  // (sums: the convective and radiative loss rates)
  sphcut::reduce<DeviceType, 2>("sphcut:heat:exchange", list->inum,
      final_sums<DeviceType, 2>(KOKKOS_LAMBDA(const int ii, double *r) {
        double &p_conv = r[0], &p_rad = r[1];
        const int i = d.av.ilist(ii);
        if (clear) d.av.st(i, F::HELD) = 0.0;
        if (!(d.av.mask(i) & gb)) return;
        const int itype = d.av.type(i);
        const sphcut::Material &mi = mat(itype);
        if (mi.cp <= 0.0) return;
        const double Ti = d.av.st(i, F::TEMP_F);
        // (NoAdd: V_i is not needed)
        const double rate = sphcut::heat_exchange<DIM>(DeviceNeighbours<DeviceType, DIM, EAGER>(d, i), mi.kappa, Ti, 0.0, &fw(i, FW0),
                                                       sphcut::NoAdd{});
        const int is_surf = has_surf ? surf(i, ComputeSurfaceLambda::FLAG) > 0.5 : 0;
        d.av.st(i, F::HELD) = sphcut::heat_rate(DIM, hl, is_surf, d.av.mask(i), rate, d.av.st(i, F::RHO_F),
                                                use_rmass ? d.av.rmass(i) : d.av.mass(itype), mi.cp, Ti, p_conv, p_rad);
      }, fin),
      wide,
      Kokkos::subview(d_red, std::make_pair(0, 2)), d_wide_acc);
  fixkk->k_state.template modify<DeviceType>();
}

/* ---------------------------------------------------------------------- */

template <class DeviceType>
int FixHeatFMFSKokkos<DeviceType>::SPHCUT_KK_FIX_PACK_FORWARD(int n, SPHCUT_KK_SENDLIST(k_sendlist, iswap),
    sphcut::kk_buf &k_buf, int, int *)
{
  return sphcut::pack_columns<DeviceType>(k_fwts, FW0, NW, n, k_sendlist, SPHCUT_KK_ISWAP(iswap), k_buf);
}

template <class DeviceType>
void FixHeatFMFSKokkos<DeviceType>::SPHCUT_KK_FIX_UNPACK_FORWARD(int n, int first, sphcut::kk_buf &k_buf)
{
  sphcut::unpack_columns<DeviceType>(k_fwts, FW0, NW, n, first, k_buf);
}

// the classic (host) path of the forward communication
template <class DeviceType>
int FixHeatFMFSKokkos<DeviceType>::pack_forward_comm(int n, int *list_, double *buf, int, int *)
{
  return stage_fwts.pack(k_fwts, FW0, NW, n, list_, buf);
}

template <class DeviceType> void FixHeatFMFSKokkos<DeviceType>::unpack_forward_comm(int n, int first, double *buf)
{
  stage_fwts.unpack(k_fwts, FW0, NW, n, first, buf);
}

/* ----------------------------------------------------------------------
   Dirichlet groups (FixHeatFMFS::setup; after the predictor and after the
   corrector this fix's hooks set their temperature in the kernels of fix
   sph/jc-thermal/kk, the heat through the clamp summed on the device)
------------------------------------------------------------------------- */

// at the setup: Dirichlet particles start at their temperature (TEMP and the predicted TEMP_F)
template <class DeviceType> void FixHeatFMFSKokkos<DeviceType>::set_dirichlet()
{
  atomKK->sync(execution_space, MASK_MASK);
  fixkk->k_state.template sync<DeviceType>();
  auto st = fixkk->k_state.template view<DeviceType>();
  auto mask = atomKK->k_mask.view<DeviceType>();
  auto db = d_dirbit;
  auto dtemp = d_dirtemp;
  const int gb = groupbit, nd = (int) dir_bits.size();
  Kokkos::parallel_for("sphcut:heat:set_dirichlet",
      sphcut::range<DeviceType>(0, atom->nlocal), KOKKOS_LAMBDA(const int i) {
        const int k = sphcut::dirichlet_index(mask(i), gb, &db(0), nd);
        if (k < 0) return;
        st(i, FixSPHJCThermal::TEMP_F) = st(i, FixSPHJCThermal::TEMP) = dtemp(k);
      });
  fixkk->k_state.template modify<DeviceType>();
}

// the heat the Dirichlet groups took since the last call: this fix's hook sums it on the device in
// the corrector's reduction of fix sph/jc-thermal/kk, the host reads it only here
template <class DeviceType> void FixHeatFMFSKokkos<DeviceType>::fetch_dirichlet()
{
  if (!qdir_pending) return;
  qdir_pending = 0;
  k_qdir.sync_host();
  q_dirichlet += k_qdir.view_host()(0);
  k_qdir.view_host()(0) = 0.0;
  k_qdir.modify_host();
}

template <class DeviceType> void FixHeatFMFSKokkos<DeviceType>::write_restart(FILE *fp)
{
  fetch_dirichlet();
  fetch_losses();
  FixHeatFMFS::write_restart(fp);
}

template <class DeviceType> void FixHeatFMFSKokkos<DeviceType>::post_run()
{
  fetch_dirichlet();
  fetch_losses();
  FixHeatFMFS::post_run();
}

// element 5 (thermal energy) is summed on the device; the others are host scalars
template <class DeviceType> double FixHeatFMFSKokkos<DeviceType>::compute_vector(int n)
{
  fetch_dirichlet();
  if (n != 4) fetch_losses();
  if (n != 4 || !fixkk) return FixHeatFMFS::compute_vector(n);
  atomKK->sync(execution_space, MASK_MASK | TYPE_MASK | RMASS_MASK);
  fixkk->k_state.template sync<DeviceType>();
  auto st = fixkk->k_state.template view<DeviceType>();
  auto mask = atomKK->k_mask.view<DeviceType>();
  auto type = atomKK->k_type.view<DeviceType>();
  auto rmass = atomKK->k_rmass.view<DeviceType>();
  auto mass = atomKK->k_mass.view<DeviceType>();
  auto mat = d_mat;
  const int gb = groupbit, use_rmass = atom->rmass_flag;
  double loc = 0.0, res = 0.0;
  Kokkos::parallel_reduce("sphcut:heat:compute_vector",
      sphcut::range<DeviceType>(0, atom->nlocal),
      KOKKOS_LAMBDA(const int i, double &sum) {
        if (!(mask(i) & gb)) return;
        const int t = type(i);
        sum += (use_rmass ? rmass(i) : mass(t)) * mat(t).cp * st(i, FixSPHJCThermal::TEMP);
      },
      loc);
  MPI_Allreduce(&loc, &res, 1, MPI_DOUBLE, MPI_SUM, world);
  return res;
}

namespace LAMMPS_NS {
template class FixHeatFMFSKokkos<LMPDeviceType>;
#ifdef LMP_KOKKOS_GPU
template class FixHeatFMFSKokkos<LMPHostType>;
#endif
}    // namespace LAMMPS_NS
