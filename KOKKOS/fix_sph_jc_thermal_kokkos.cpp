/* ----------------------------------------------------------------------
   sphcut - fix sph/jc-thermal/kk

   One step on the device (doc/design.md):
     initial_integrate  one kernel: keep the old rates, kick, drift,
                        predictor, radial return (sphcut_solid.h), the
                        rates zeroed, then the hooks after the first half
     pre_force          the rates were zeroed by initial_integrate (one kernel
                        zeroing them only after reneighbouring), then the force state
                        to the ghosts by device forward communication
     final_integrate    one reduction: the hooks before the corrector,
                        corrector, radial return, plastic heat, the hooks
                        after the corrector, and the sums into device
                        views: plastic work and this rank's Courant limit
                        (k_dtlim), the hooks' values through their final
                        (their own accumulators and dt slots)
     end_of_step        every dtevery-th step: that view with the attached
                        styles' dt slots to the host (the one host round
                        trip), the new dt (one MPI_Allreduce); the plastic
                        work stays summed on the device between; the state
                        to the host only on output steps
   The hooks (sphcut_hooks_kokkos.h) are the other /kk styles' per-particle
   work in these kernels: each style takes its slot in its init
   (sphcut::HookHost::set_hook) and fills it, when this fix builds a kernel,
   from its arm callback; this fix calls them at fixed points without knowing
   what they do (which style holds which slot: that header).  No style runs a
   kernel of its own for them, and none costs a pass over the state rows.
   Where nothing reads v, the state or the corrector's sums before the next
   step (no dt, output or other fix's end_of_step step, not the run's last:
   defers_corrector), final_integrate leaves its reduction to the next
   step's initial_integrate, whose one kernel then runs each particle's
   corrector and its first half (CorrectThenFirstHalf): one launch and one
   pass over the state rows fewer a step.
   Host copies of the state otherwise happen only where LAMMPS needs it on
   the host: restart, setup, and with migrate host exchange and sorting.

   Reneighbouring: a fix with an Atom grow callback makes LAMMPS 29Sep2021
   exchange, sort and build ghosts on the host (x, v, f and the whole
   state copied both ways, about 45 ns per atom and more than a step).
   The /kk fix (keyword migrate device, the default) therefore holds the
   grow callback only between runs (where delete_atoms, create_atoms,
   write_restart's exchange ... move the rows by index, on the host).  At
   the setup of a run (setup_pre_exchange, before LAMMPS reorders
   anything) it labels each row with its atom's tag and drops the
   callback, so LAMMPS keeps exchange, sorting and borders on the device;
   after every reneighbouring (post_neighbor, before any force) the rows
   follow their atoms by tag on the device (sphcut_migrate_kokkos.h): on
   one rank two kernels; on several, the rows of atoms that left a rank
   are packed on the device and sent to the other ranks (host staging, one
   MPI_Allgatherv of those few rows), and each new local atom takes its old
   row or a received one.  Atoms lost drop out, atoms created get a new
   row; post_run takes the callback back.  migrate host (or atoms without
   IDs) keeps the callback: LAMMPS moves the state on the host.
------------------------------------------------------------------------- */

#include "fix_sph_jc_thermal_kokkos.h"

#include "atom_kokkos.h"
#include "atom_masks.h"
#include "comm.h"
#include "compute.h"
#include "error.h"
#include "kokkos.h"
#include "force.h"
#include "atom_vec.h"
#include "memory_kokkos.h"
#include "modify.h"
#include "neighbor.h"
#include "output.h"
#include "pair.h"
#include "update.h"

#include "neigh_list_kokkos.h"
#include "sphcut_checks.h"
#include "sphcut_compat.h"
#include "sphcut_kokkos.h"
#include "sphcut_solid.h"

#include <algorithm>
#include <cstring>

using namespace LAMMPS_NS;
using namespace FixConst;

namespace {

/* first half of the step (initial_integrate) for particle i on its state row s: the row in the
   state view (operator()(i), in place) or its copy in the team's scratch (the staged kernel,
   operator()(team): sphcut::stage_in / stage_out).  The rates are zeroed here, after the
   predictor has saved them (DRHO_O, ...), instead of in a kernel of their own at pre_force: one
   launch fewer on steps without reneighbouring (pre_force zeroes them again where atoms may have
   moved, been exchanged or created).  Then the hooks after the first half (sphcut_hooks_kokkos.h),
   on the row this kernel just wrote.  zero_f: the forces of every local particle zeroed after the
   half kick has read them (clear_f_active: LAMMPS' force clear of this step skipped,
   external_force_clear)                                                                        */
template <class DeviceType> struct FirstHalf {
  typedef DeviceType device_type;
  typedef ArrayTypes<DeviceType> AT;
  typename sphcut::AtomTypes<DeviceType>::x x;
  typename sphcut::AtomTypes<DeviceType>::v v;
  typename sphcut::AtomTypes<DeviceType>::f f;
  typename AT::t_int_1d_const mask, type;
  typename sphcut::AtomTypes<DeviceType>::scalar_const rmass, mass;
  typename AT::t_double_2d state;
  Kokkos::View<const sphcut::Material *, typename DeviceType::memory_space> mat;
  int groupbit, toolbit, clampbit, use_rmass, zero_f, n;
  double dt, dtf;
  sphcut::FirstHalfHooks<DeviceType> hooks;

  KOKKOS_INLINE_FUNCTION void particle(const int i, double *s) const
  {
    const int mi = mask(i);
    if (mi & groupbit) {
      const int t = type(i);
      const double m = use_rmass ? rmass(i) : mass(t);
      double xi[3] = {x(i, 0), x(i, 1), x(i, 2)};
      double vi[3] = {v(i, 0), v(i, 1), v(i, 2)};
      const double fi[3] = {f(i, 0), f(i, 1), f(i, 2)};
      sphcut::integrate_first_half(mat(t), sphcut::role_from_mask(mi, toolbit, clampbit), dt, dtf / m, xi, vi, fi, s);
      for (int d = 0; d < 3; d++) {
        x(i, d) = xi[d];
        v(i, d) = vi[d];
      }
    }
    if (zero_f)
      for (int d = 0; d < 3; d++) f(i, d) = 0.0;
    sphcut::zero_rates(s);
    hooks.after_first_half(i, mi, s);
  }
  KOKKOS_INLINE_FUNCTION void operator()(const int i) const { particle(i, &state(i, 0)); }
  KOKKOS_INLINE_FUNCTION void operator()(const typename Kokkos::TeamPolicy<DeviceType>::member_type &t) const
  {
    const int first = t.league_rank() * sphcut::STAGE_ROWS;
    const int cnt = n - first < sphcut::STAGE_ROWS ? n - first : sphcut::STAGE_ROWS;
    double *sh = sphcut::stage_in(t, state, first, cnt);
    const int ncol = (int) state.extent(1);
    for (int l = t.team_rank(); l < cnt; l += t.team_size()) particle(first + l, sh + l * ncol);
    sphcut::stage_out(t, state, first, cnt, sh);
  }
};

/* second half of the step with the two sums the host needs: the plastic work of the step (WORK) and
   this rank's Courant limit (DT, computed from the final v and T, as the CPU fix does at
   end_of_step); written into the device view k_dtlim (STEP_WORK, STEP_DT) by final, no host round
   trip here.  Each particle: the hooks before the corrector, its corrector, the hooks after it,
   whose values (NVALUES of sphcut::CorrectorHooks) follow the two sums and go to the hooks' final */
template <class DeviceType> struct SecondHalf {
  typedef DeviceType device_type;
  typedef double value_type[];
  typedef sphcut::CorrectorHooks<DeviceType> Hooks;
  enum { WORK = 0, DT = 1, NOWN = 2, NVAL = NOWN + Hooks::NVALUES };
  const unsigned value_count = NVAL;
  typedef ArrayTypes<DeviceType> AT;
  typename sphcut::AtomTypes<DeviceType>::v v;
  typename sphcut::AtomTypes<DeviceType>::f_const f;
  typename AT::t_int_1d_const mask, type;
  typename sphcut::AtomTypes<DeviceType>::scalar_const rmass, mass;
  typename AT::t_double_2d state;
  Kokkos::View<const sphcut::Material *, typename DeviceType::memory_space> mat;
  Kokkos::View<const double *, typename DeviceType::memory_space> h;
  int groupbit, toolbit, clampbit, use_rmass, want_dt;
  double dt, dtf, cfl, vmax, tmax;
  Hooks hooks;

  // the minima among the values (sphcut::reduce's wide path; the others are sums)
  KOKKOS_INLINE_FUNCTION static constexpr bool is_min(int k) { return k == DT || (k >= NOWN && Hooks::is_min(k - NOWN)); }
  KOKKOS_INLINE_FUNCTION void init(value_type r) const
  {
    for (int k = 0; k < NVAL; k++) r[k] = is_min(k) ? 1.0e300 : 0.0;
  }
  KOKKOS_INLINE_FUNCTION void join(SPHCUT_KK_VOLATILE value_type d, const SPHCUT_KK_VOLATILE value_type s) const
  {
    for (int k = 0; k < NVAL; k++) {
      if (!is_min(k)) d[k] += s[k];
      else if (s[k] < d[k]) d[k] = s[k];
    }
  }
  // the plastic work accumulates on the device (the result's own element holds the sum so far):
  // the host reads it only when it needs it (a dt step, an output), with no copy on other steps
  Kokkos::View<double *, typename DeviceType::memory_space> result;
  KOKKOS_INLINE_FUNCTION void final(value_type r) const
  {
    result(FixSPHJCThermalKokkosBase::STEP_WORK) = r[WORK] + result(FixSPHJCThermalKokkosBase::STEP_WORK);
    result(FixSPHJCThermalKokkosBase::STEP_DT) = r[DT];
    hooks.final(&r[NOWN]);
  }

  KOKKOS_INLINE_FUNCTION void operator()(const int i, value_type r) const { row(i, &state(i, 0), r); }
  // particle i on its state row s (in place or a staged copy: CorrectThenFirstHalf)
  KOKKOS_INLINE_FUNCTION void row(const int i, double *s, value_type r) const
  {
    const int mi = mask(i);
    hooks.before_corrector(i, mi, s);
    if (!(mi & groupbit)) return;
    const int t = type(i);
    const int role = sphcut::role_from_mask(mi, toolbit, clampbit);
    const double m = use_rmass ? rmass(i) : mass(t);
    double vi[3] = {v(i, 0), v(i, 1), v(i, 2)};
    const double fi[3] = {f(i, 0), f(i, 1), f(i, 2)};
    r[WORK] += sphcut::integrate_second_half(mat(t), role, dt, dtf / m, m, vi, fi, s);
    hooks.after_corrector(i, mi, t, m, mat(t), s, &r[NOWN]);
    for (int d = 0; d < 3; d++) v(i, d) = vi[d];
    if (want_dt) {
      const double d = sphcut::particle_dt(mat(t), role, h(t), vi, s[FixSPHJCThermal::TEMP], cfl, vmax, tmax);
      if (d < r[DT]) r[DT] = d;
    }
  }
};

/* the corrector of the step before (SecondHalf, left pending by that step's final_integrate:
   FixSPHJCThermalKokkos::defers_corrector) and the first half of this step (FirstHalf) in one pass,
   each particle's row read and written once: its corrector, then its kick, drift and predictor
   from the same forces.  Each reads only its own particle's data, and a hook that reads other
   particles' reads none that this kernel writes (sphcut_hooks_kokkos.h); so the order within a
   particle is the whole order: the same arithmetic as the two kernels.  The
   reduction is the corrector's (its sums; no dt limits: a step whose limits the host reads is never
   deferred)                                                                                     */
template <class DeviceType> struct CorrectThenFirstHalf {
  typedef DeviceType device_type;
  typedef double value_type[];
  enum { NVAL = SecondHalf<DeviceType>::NVAL };
  const unsigned value_count = NVAL;
  SecondHalf<DeviceType> c;
  FirstHalf<DeviceType> p;
  KOKKOS_INLINE_FUNCTION void init(value_type r) const { c.init(r); }
  KOKKOS_INLINE_FUNCTION void join(SPHCUT_KK_VOLATILE value_type d, const SPHCUT_KK_VOLATILE value_type s) const { c.join(d, s); }
  KOKKOS_INLINE_FUNCTION static constexpr bool is_min(int k) { return SecondHalf<DeviceType>::is_min(k); }
  KOKKOS_INLINE_FUNCTION void final(value_type r) const { c.final(r); }
  KOKKOS_INLINE_FUNCTION void row(const int i, double *s, value_type r) const
  {
    c.row(i, s, r);
    p.particle(i, s);
  }
  KOKKOS_INLINE_FUNCTION void operator()(const int i, value_type r) const { row(i, &p.state(i, 0), r); }
};

/* the same on team-staged rows (sphcut::stage_in / stage_out, as FirstHalf's team kernel): each
   team joins its threads' sums (team_reduce) and its first thread joins them into the wide
   reduction's accumulator (sphcut::WideReduce::join: atomics, the last team runs the final), on
   every backend                                                                                  */
template <class DeviceType> struct CorrectThenFirstHalfStaged {
  typedef DeviceType device_type;
  enum { NVAL = CorrectThenFirstHalf<DeviceType>::NVAL };
  sphcut::WideReduce<DeviceType, NVAL, CorrectThenFirstHalf<DeviceType>> w;
  KOKKOS_INLINE_FUNCTION void operator()(const typename Kokkos::TeamPolicy<DeviceType>::member_type &t) const
  {
    const auto &k = w.f;
    const int first = t.league_rank() * sphcut::STAGE_ROWS;
    const int cnt = w.end - first < sphcut::STAGE_ROWS ? w.end - first : sphcut::STAGE_ROWS;
    double *sh = sphcut::stage_in(t, k.p.state, first, cnt);
    const int ncol = (int) k.p.state.extent(1);
    double r[NVAL];
    k.init(r);
    for (int l = t.team_rank(); l < cnt; l += t.team_size()) k.row(first + l, sh + l * ncol, r);
    sphcut::stage_out(t, k.p.state, first, cnt, sh);
    for (int q = 0; q < NVAL; q++) {
      if (k.is_min(q)) t.team_reduce(Kokkos::Min<double>(r[q]));
      else t.team_reduce(Kokkos::Sum<double>(r[q]));
    }
    Kokkos::single(Kokkos::PerTeam(t), [&]() { w.join(r, t.league_size()); });
  }
};

}    // namespace

/* ---------------------------------------------------------------------- */

template <class DeviceType>
FixSPHJCThermalKokkos<DeviceType>::FixSPHJCThermalKokkos(LAMMPS *lmp, int narg, char **arg) :
    FixSPHJCThermalKokkosBase(sphcut::require_kokkos(lmp, "Fix sph/jc-thermal/kk"), narg, arg),
    remap(0), nrows(0), rowtag(nullptr)
{
  kokkosable = 1;
  forward_comm_device = 1;
  atomKK = (AtomKokkos *) atom;
  execution_space = ExecutionSpaceFromDevice<DeviceType>::space;
  datamask_read = X_MASK | V_MASK | F_MASK | MASK_MASK | TYPE_MASK | RMASS_MASK;
  datamask_modify = X_MASK | V_MASK;

  // the base class allocated a host array: replace it by the DualView's host view
  memory->destroy(state);
  state = nullptr;
  grow_arrays(atom->nmax);
  for (int i = 0; i < atom->nlocal; i++) initialize_atom(i);
  k_state.modify_host();
  remap = migrate_device && atom->tag_enable;
  k_dtlim = DAT::tdual_double_1d("sph/jc-thermal:dtlim", SLOT0);
  k_dtlim.view_host()(STEP_WORK) = 0.0;
  k_dtlim.view_host()(STEP_DT) = 1.0e300;
  k_dtlim.modify_host();
  k_dtlim.template sync<DeviceType>();
  hook_type = &typeid(sphcut::IntegratorHooks<DeviceType>);    // (set_hook: the styles on this device type)
}

/* an attached style gets a slot of k_dtlim for its dt limit, once: a style attached again (each
   init) keeps its slot and the limit it last wrote there, as a CPU style keeps the limit it last
   computed; a new style (dt_slot -1, or a slot of another fix sph/jc-thermal/kk) gets a new slot
   holding no limit.  Slots are not reused: a deleted style's slot stays unread.            */
void FixSPHJCThermalKokkosBase::attach(sphcut::AttachedStyle *style)
{
  FixSPHJCThermal::attach(style);
  const int k = style->dt_slot;
  if (k >= 0 && k < (int) slot_owner.size() && slot_owner[k] == style) return;
  style->dt_slot = (int) slot_owner.size();
  slot_owner.push_back(style);
  k_dtlim.sync_host();
  DAT::tdual_double_1d grown("sph/jc-thermal:dtlim", SLOT0 + slot_owner.size());
  for (int i = 0; i < (int) k_dtlim.extent(0); i++) grown.view_host()(i) = k_dtlim.view_host()(i);
  grown.view_host()(SLOT0 + style->dt_slot) = 1.0e300;
  grown.modify_host();
  grown.sync_device();
  k_dtlim = grown;
}

// a hook's owner that still exists keeps its slot (sphcut::HookHost::set_hook)
bool FixSPHJCThermalKokkosBase::hook_owner_alive(const sphcut::AttachedStyle *owner) const
{
  for (auto *st : live_styles())
    if (st == owner) return true;
  return false;
}

// at each setup: the attached styles and the hooks of those deleted since
void FixSPHJCThermalKokkosBase::prune_attached()
{
  FixSPHJCThermal::prune_attached();
  prune_hooks(live_styles());
}

// the minimum of this step's limits that the attached styles hold in their slots (host copy of
// k_dtlim current)
double FixSPHJCThermalKokkosBase::device_limits()
{
  double m = 1.0e300;
  for (auto *st : timed)
    if (st->dt_slot >= 0 && st->dt_limit_on_device()) m = std::min(m, k_dtlim.view_host()(SLOT0 + st->dt_slot));
  return m;
}

template <class DeviceType> FixSPHJCThermalKokkos<DeviceType>::~FixSPHJCThermalKokkos()
{
  memoryKK->destroy_kokkos(k_state, state);
  memoryKK->destroy_kokkos(k_rowtag, rowtag);
  state = nullptr;    // the base destructor must not free it
}

// migrated_rows: the rows this rank took from other ranks in this run (0-d bigint; tests)
template <class DeviceType> void *FixSPHJCThermalKokkos<DeviceType>::extract(const char *name, int &dim)
{
  dim = 0;
  if (strcmp(name, "migrated_rows") == 0) return &mig.received;
  if (strcmp(name, "migrate_device") == 0) return &remap;
  return nullptr;
}

/* LAMMPS 29Sep2021 matches the state in a restart file to a fix by ID and style name: the /kk fix
   goes by the name of the CPU style (as LAMMPS itself matches from 2022 on, suffix stripped), so a
   restart written by either continues under the other.  kokkosable tells the two apart.        */
template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::post_constructor()
{
  delete[] style;
  style = utils::strdup("sph/jc-thermal");
}

template <class DeviceType> int FixSPHJCThermalKokkos<DeviceType>::setmask()
{
  // end_of_step every step: the new dt, and the host copy of the state before output
  return FixSPHJCThermal::setmask() | END_OF_STEP | (remap ? PRE_EXCHANGE | POST_NEIGHBOR : 0);
}

/* ---------------------------------------------------------------------- */

template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::init()
{
  FixSPHJCThermal::init();
  if (!force->pair_match("^sph/jc-thermal", 0)->kokkosable)
    error->all(FLERR, "Fix sph/jc-thermal/kk requires pair_style sph/jc-thermal/kk (run with -sf kk)");
  kept_to_force = others_keep_out(false);
  clear_f = force_clear_allowed();
  // the first-half kernel on staged rows (staged(): by size on a GPU; SPHCUT_STAGE_ROWS 0 or 1
  // forces, 2 stages in teams of 2 threads on a host backend: the tests of the staged kernels'
  // team reductions)
  stage_rows = sphcut::env_switch(lmp, "SPHCUT_STAGE_ROWS", "Fix sph/jc-thermal/kk", -1, 2);
  host_team = stage_rows == 2 ? 2 : 1;
  wide = sphcut::wide_choice<DeviceType>(lmp, "Fix sph/jc-thermal/kk");
  fuse = fuse_allowed();
  defer_step = -1;
  // fix print and fix halt (LAMMPS' host styles) evaluate variables and change no per-atom array,
  // but declare every array modified on the host (Fix's default datamask_modify, ALL_MASK): under
  // /kk each of their steps would then copy all atom arrays back to the device.  What their
  // variables may read stays synchronised to the host before them (datamask_read)
  for (auto *f : sphcut::fix_list(modify))
    if (!f->kokkosable && (utils::strmatch(f->style, "^print$") || utils::strmatch(f->style, "^halt$")))
      f->datamask_modify = EMPTY_MASK;
  // the other sphcut styles (those that attach to this fix) read and write the state: under /kk
  // only their /kk variants do that on the device (a CPU variant would read a stale host copy)
  for (auto *f : sphcut::fix_list(modify))
    if (dynamic_cast<sphcut::AttachedStyle *>(f) && !f->kokkosable)
      error->all(FLERR, "Fix sph/jc-thermal/kk: fix {} {} is the CPU style; use its /kk variant "
                 "(-sf kk, or the style name with /kk)", f->id, f->style);
  for (auto *c : sphcut::compute_list(modify))
    if (dynamic_cast<sphcut::AttachedStyle *>(c) && !c->kokkosable)
      error->all(FLERR, "Fix sph/jc-thermal/kk: compute {} {} is the CPU style; use its /kk variant "
                 "(-sf kk, or the style name with /kk)", c->id, c->style);
  // the state comes to the host every peratom_every steps and on output steps (thermo, dumps);
  // LAMMPS refuses consumers of f_ID per-atom values at other steps.  By default the greatest
  // common divisor of the thermo and dump intervals (every step without either): each dump
  // step is an output step, at which the host copy is current, and LAMMPS' check of a dump
  // (its interval a multiple of peratom_freq) then passes
  if (peratom_every > 0) peratom_freq = peratom_every;
  else {
    auto gcd = [](bigint a, bigint b) {
      while (b > 0) {
        const bigint r = a % b;
        a = b;
        b = r;
      }
      return a;
    };
    bigint g = std::max(output->thermo_every, 0);
    for (int i = 0; i < output->ndump; i++) g = gcd(g, std::max(output->every_dump[i], 0));
    peratom_freq = g > 0 ? (int) g : 1;
  }
  sphcut::fence_timers() = fence == 1;
  atomKK->k_mass.modify<LMPHostType>();
  atomKK->k_mass.sync<DeviceType>();
  upload_tables();
}

template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::upload_tables()
{
  const int n = atom->ntypes + 1;
  d_mat = sphcut::to_device<sphcut::Material, DeviceType>(model->materials(), n, "sph/jc-thermal:mat");
  std::vector<double> h(n, 0.0);
  for (int t = 1; t < n; t++) h[t] = model->smoothing_length(t);
  d_h = sphcut::to_device<double, DeviceType>(h.data(), n, "sph/jc-thermal:h");
}

/* ----------------------------------------------------------------------
   setup: the state of new atoms is completed on the host (it may need an
   atom-style variable), then the forces of the setup step on the device
------------------------------------------------------------------------- */

template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::setup_pre_force(int vflag)
{
  atomKK->sync(Host, V_MASK | MASK_MASK | TYPE_MASK | RMASS_MASK);
  k_state.sync_host();
  setup_state();
  k_state.modify_host();
  pre_force(vflag);
}

template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::setup(int vflag)
{
  settle_corrector();    // (none is left pending across runs: post_run)
  atomKK->sync(execution_space, datamask_read);
  FixSPHJCThermal::setup(vflag);    // timers, first stable dt (stable_dt below, on the device)
  outputs_step = -1;
  // from here to post_run the forces are zeroed by this fix's kernels (force_clear_allowed); the
  // setup's own were cleared by LAMMPS before its forces
  if (clear_f && !clear_f_active) {
    saved_force_clear = sphcut::IntegrateForceClear::flag(update->integrate);
    sphcut::IntegrateForceClear::flag(update->integrate) = 1;
    clear_f_active = 1;
  }
  // the device continues the host's plastic work (restart, earlier runs)
  k_dtlim.sync_host();
  k_dtlim.view_host()(STEP_WORK) = plastic_work;
  k_dtlim.modify_host();
}

// the plastic work summed on the device since the setup, into the host's plastic_work
template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::fetch_work()
{
  settle_corrector();
  k_dtlim.sync_host();
  plastic_work = k_dtlim.view_host()(STEP_WORK);
}

template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::write_restart(FILE *fp)
{
  fetch_work();
  FixSPHJCThermal::write_restart(fp);
}

template <class DeviceType> double FixSPHJCThermalKokkos<DeviceType>::stable_dt()
{
  k_state.template sync<DeviceType>();
  auto v = atomKK->k_v.view<DeviceType>();
  auto mask = atomKK->k_mask.view<DeviceType>();
  auto type = atomKK->k_type.view<DeviceType>();
  auto mat = d_mat;
  auto h = d_h;
  const int gb = groupbit, tb = toolbit, cb = clampbit;
  auto st = k_state.template view<DeviceType>();
  const double c = cfl, vm = vmax, tm = tmax;
  double dtloc = 1.0e300;
  Kokkos::parallel_reduce("sphcut:sph:stable_dt",
      sphcut::range<DeviceType>(0, atom->nlocal),
      KOKKOS_LAMBDA(const int i, double &m) {
        if (!(mask(i) & gb)) return;
        const double vi[3] = {v(i, 0), v(i, 1), v(i, 2)};
        const int t = type(i);
        const double d = sphcut::particle_dt(mat(t), sphcut::role_from_mask(mask(i), tb, cb), h(t), vi,
                                             st(i, FixSPHJCThermal::TEMP), c, vm, tm);
        if (d < m) m = d;
      },
      Kokkos::Min<double>(dtloc));
  // with the limits the attached styles hold in their slots (setup: host copies are due anyway)
  k_dtlim.sync_host();
  return finish_dt(std::min(dtloc, device_limits()));
}

// a particle ran away (the step's minimum came back -1): the host's velocities, positions and
// tags name it
template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::report_runaway()
{
  atomKK->sync(Host, V_MASK | X_MASK | TAG_MASK | MASK_MASK | TYPE_MASK);
  k_state.sync_host();    // the densities, if no particle is too fast
  FixSPHJCThermal::report_runaway();
}

// particles closer than half their spacing, counted on the device from the pair's list
template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::check_close_pairs()
{
  const double frac = 0.5;
  double count = 0.0, rmin = 1.0e300;
  Pair *pair = force->pair_match("^sph/jc-thermal", 0);
  if (pair->execution_space == execution_space && pair->list) {
    auto *kl = static_cast<NeighListKokkos<DeviceType> *>(pair->list);
    auto neighbors = kl->d_neighbors;
    auto numneigh = kl->d_numneigh;
    auto ilist = kl->d_ilist;
    auto x = atomKK->k_x.view<DeviceType>();
    auto type = atomKK->k_type.view<DeviceType>();
    std::vector<double> sp(atom->ntypes + 1, 0.0);
    for (int t = 1; t <= atom->ntypes; t++) sp[t] = model->spacing(t);
    auto dp = sphcut::to_device<double, DeviceType>(sp.data(), atom->ntypes + 1, "sph/jc-thermal:dp");
    const int nlocal = atom->nlocal;
    // a full list sees each pair twice; a half list sees local-ghost pairs on both ranks without newton
    const int full = kl->d_numneigh.extent(0) > 0 && lmp->kokkos->neighflag == FULL;
    const double wlocal = full ? 0.5 : 1.0, wghost = full ? 0.5 : (force->newton_pair ? 1.0 : 0.5);
    Kokkos::parallel_reduce("sphcut:sph:check_close_pairs",
        sphcut::range<DeviceType>(0, kl->inum),
        KOKKOS_LAMBDA(const int ii, double &c, double &r) {
          const int i = ilist(ii);
          for (int jj = 0; jj < numneigh(i); jj++) {
            const int j = neighbors(i, jj) & NEIGHMASK;
            const double d = 0.5 * (dp(type(i)) + dp(type(j)));
            if (!(d > 0.0)) continue;
            const double dx = x(i, 0) - x(j, 0), dy = x(i, 1) - x(j, 1), dz = x(i, 2) - x(j, 2);
            const double q = sqrt(dx * dx + dy * dy + dz * dz) / d;
            if (q >= frac) continue;
            c += j < nlocal ? wlocal : wghost;
            if (q < r) r = q;
          }
        },
        count, Kokkos::Min<double>(rmin));
  }
  sphcut::report_close_pairs(lmp, count, rmin, frac);
}

/* ---------------------------------------------------------------------- */

/* the views and constants the integrator's two kernels (FirstHalf, SecondHalf) share */

template <class DeviceType> template <class K> void FixSPHJCThermalKokkos<DeviceType>::integrator_views(K &k)
{
  k.v = atomKK->k_v.view<DeviceType>();
  k.f = atomKK->k_f.view<DeviceType>();
  k.mask = atomKK->k_mask.view<DeviceType>();
  k.type = atomKK->k_type.view<DeviceType>();
  k.rmass = atomKK->k_rmass.view<DeviceType>();
  k.mass = atomKK->k_mass.view<DeviceType>();
  k.state = k_state.template view<DeviceType>();
  k.mat = d_mat;
  k.groupbit = groupbit;
  k.toolbit = toolbit;
  k.clampbit = clampbit;
  k.use_rmass = atom->rmass_flag;
  k.dt = dtv;
  k.dtf = dtf;
}

/* ---------------------------------------------------------------------- */

template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::initial_integrate(int)
{
  sphcut::FencedTimer timer(cpu_time);
  atomKK->sync(execution_space, datamask_read);
  k_state.template sync<DeviceType>();
  FirstHalf<DeviceType> k;
  integrator_views(k);
  k.x = atomKK->k_x.view<DeviceType>();
  k.hooks = arm_hooks<DeviceType>({sphcut::HookCall::FIRST_HALF, update->ntimestep, 0, kept_to_force}).first_half;
  const int zero_f = k.zero_f = clear_f_active;
  k.n = atom->nlocal;
  if (corrector_pending) {
    // the step before left its corrector to this kernel (defers_corrector)
    corrector_pending = 0;
    CorrectThenFirstHalf<DeviceType> c;
    c.p = k;
    corrector_views(c.c, false);
    if (staged(k.n) && k.n > 0) {
      const CorrectThenFirstHalfStaged<DeviceType> w{
          sphcut::wide_reducer<DeviceType, CorrectThenFirstHalf<DeviceType>::NVAL>("sphcut:sph:final_integrate", k.n, c, d_second_acc)};
      Kokkos::parallel_for("sphcut:sph:correct_then_first_half_staged",
                           sphcut::stage_policy<DeviceType>(k.n, (int) k.state.extent(1), host_team), w);
    } else
      sphcut::reduce<DeviceType, CorrectThenFirstHalf<DeviceType>::NVAL>("sphcut:sph:correct_then_first_half", k.n, c, wide, d_second, d_second_acc);
    corrector_done();
  } else if (staged(k.n))
    Kokkos::parallel_for("sphcut:sph:initial_integrate_staged",
                         sphcut::stage_policy<DeviceType>(k.n, (int) k.state.extent(1), host_team), k);
  else
    Kokkos::parallel_for("sphcut:sph:initial_integrate", sphcut::range<DeviceType>(0, k.n), k);
  k_state.template modify<DeviceType>();
  atomKK->modified(execution_space, datamask_modify | (zero_f ? F_MASK : 0));
  rates_zeroed_step = update->ntimestep;
}

/* ---------------------------------------------------------------------- */

template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::pre_force(int)
{
  sphcut::FencedTimer timer(cpu_time);
  // rows for the ghosts the forward communication fills (remap mode grows here, not in a callback)
  if ((int) k_state.extent(0) < atom->nmax) grow_on_device(atom->nmax);
  k_state.template sync<DeviceType>();
  auto st = k_state.template view<DeviceType>();
  // zeroed by initial_integrate of this step unless the atoms were rebuilt since (reneighbouring:
  // exchange, sorting, created atoms) or this is the setup
  const bool zeroed = !update->setupflag && rates_zeroed_step == update->ntimestep && neighbor->ago != 0;
  if (!zeroed) {
    // the forces too when this fix clears them (clear_f_active), where LAMMPS would clear them
    // after the atoms were rebuilt: a guard (exchanged and sorted atoms land in rows initial_integrate
    // zeroed or that held no forces; f travels with neither), free in this launch
    const int zero_f = clear_f_active && !update->setupflag;
    if (zero_f) atomKK->sync(execution_space, F_MASK);
    auto f = atomKK->k_f.view<DeviceType>();
    Kokkos::parallel_for("sphcut:sph:pre_force",
        sphcut::range<DeviceType>(0, atom->nlocal), KOKKOS_LAMBDA(const int i) {
          sphcut::zero_rates(&st(i, 0));
          if (zero_f)
            for (int d = 0; d < 3; d++) f(i, d) = 0.0;
        });
    k_state.template modify<DeviceType>();
    if (zero_f) atomKK->modified(execution_space, F_MASK);
  }
  // the force state to the ghosts: on the device unless LAMMPS takes the classic path
  sphcut::forward_comm(comm, this);
}

template <class DeviceType>
int FixSPHJCThermalKokkos<DeviceType>::SPHCUT_KK_FIX_PACK_FORWARD(int n, SPHCUT_KK_SENDLIST(k_sendlist, iswap),
    sphcut::kk_buf &k_buf, int, int *)
{
  return sphcut::pack_columns<DeviceType>(k_state, FORWARD_FIRST, NFORWARD, n, k_sendlist, SPHCUT_KK_ISWAP(iswap), k_buf);
}

template <class DeviceType>
void FixSPHJCThermalKokkos<DeviceType>::SPHCUT_KK_FIX_UNPACK_FORWARD(int n, int first, sphcut::kk_buf &k_buf)
{
  sphcut::unpack_columns<DeviceType>(k_state, FORWARD_FIRST, NFORWARD, n, first, k_buf);
}

/* ---------------------------------------------------------------------- */

/* the corrector's kernel arguments (SecondHalf): now, those of this step's final_integrate; else
   those of the corrector the step before left pending (defers_corrector), run with this step's
   first half (initial_integrate) or alone (settle_corrector): that step's dt, no dt limits, the
   hooks armed for that step (pending_step) */
template <class DeviceType> template <class K> void FixSPHJCThermalKokkos<DeviceType>::corrector_views(K &k, bool now)
{
  integrator_views(k);
  if (!now) {
    k.dt = pending_dt;
    k.dtf = pending_dtf;
  }
  k.h = d_h;
  k.want_dt = now && cfl > 0.0;
  k.cfl = cfl;
  k.vmax = vmax;
  k.tmax = tmax;
  // into the device views (no fence): final writes the sums into k_dtlim (and the hooks' final into
  // theirs: a style's dt slot is in k_dtlim too); end_of_step reads k_dtlim with the styles' slots
  k_dtlim.template sync<DeviceType>();
  k.result = k_dtlim.template view<DeviceType>();
  k.hooks = arm_hooks<DeviceType>({sphcut::HookCall::CORRECTOR, now ? update->ntimestep : pending_step,
                                   k.want_dt, kept_to_force}).corrector;
  if ((int) d_second.extent(0) != K::NVAL)
    d_second = Kokkos::View<double *, typename DeviceType::memory_space>("sph:second", K::NVAL);
}

// what the corrector's kernel modified (the hooks' owners mark their own views in their arms)
template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::corrector_done()
{
  k_dtlim.template modify<DeviceType>();
  k_state.template modify<DeviceType>();
  atomKK->modified(execution_space, V_MASK);
}

template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::final_integrate()
{
  sphcut::FencedTimer timer(cpu_time);
  if (defers_corrector()) {
    // the next step's initial_integrate runs this corrector in its kernel (the same dt: a step
    // that changes it is not deferred), with the hooks of this step (HookCall::step)
    corrector_pending = 1;
    pending_step = update->ntimestep;
    pending_dt = dtv;
    pending_dtf = dtf;
    return;
  }
  corrector(true);
}

// the corrector as a kernel of its own: this step's (now), or the one left pending
template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::corrector(bool now)
{
  atomKK->sync(execution_space, datamask_read);
  k_state.template sync<DeviceType>();
  SecondHalf<DeviceType> k;
  corrector_views(k, now);
  sphcut::reduce<DeviceType, SecondHalf<DeviceType>::NVAL>("sphcut:sph:final_integrate", atom->nlocal, k, wide, d_second, d_second_acc);
  corrector_done();
}

/* the corrector left pending (defers_corrector) now, in a kernel of its own: before anything reads
   the state, v or the step's sums outside the steps' kernels (the end of a run, a restart, an
   output) */
template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::settle_corrector()
{
  if (!corrector_pending) return;
  corrector_pending = 0;
  corrector(false);
}

/* whether this step's corrector waits for the next step's initial_integrate, which runs it in its
   first-half kernel (CorrectThenFirstHalf: one pass over the state rows and one launch fewer a
   step).  Between this step's final_integrate and the next step's initial_integrate nothing may
   then read v, the state or the corrector's sums: not at a dt step (end_of_step reads the Courant
   limit), an output step or a peratom_freq step (the host copies), the run's last step, nor where
   another fix's end_of_step runs this step (fuse_watch: fix print, halt, ave/time ... every
   nevery steps; an attached style only if its end_of_step touches the particles).  init sets fuse
   (fuse_allowed); the answer is kept for the step */
template <class DeviceType> bool FixSPHJCThermalKokkos<DeviceType>::defers_corrector()
{
  const bigint s = update->ntimestep;
  if (s == defer_step) return defer_now;
  defer_step = s;
  defer_now = fuse && !update->setupflag && s < update->laststep && !(cfl > 0.0 && dt_step()) &&
      s != output->next && s % peratom_freq != 0;
  for (const Fix *f : fuse_watch)
    if (f->nevery > 0 && s % f->nevery == 0) defer_now = false;
  return defer_now;
}

/* whether a step's corrector may wait for the next step's first half at all (defers_corrector):
   the Verlet integrator, and no other fix (but the attached sphcut styles) integrates, that is has
   initial_integrate (it would read v or the state before the corrector of the step before) or
   final_integrate (after this fix's, it would read them before the corrector).  The fixes with
   end_of_step whose steps are then not deferred go into fuse_watch */
template <class DeviceType> bool FixSPHJCThermalKokkos<DeviceType>::fuse_allowed()
{
  fuse_watch.clear();
  if (!utils::strmatch(update->integrate_style, "^verlet") || utils::strmatch(update->integrate_style, "^verlet/split"))
    return false;
  for (auto *f : sphcut::fix_list(modify)) {
    if (f == this) continue;
    const int m = sphcut::fix_mask(modify, f);
    auto *st = dynamic_cast<sphcut::AttachedStyle *>(f);
    if (!st && (m & (FixConst::INITIAL_INTEGRATE | FixConst::FINAL_INTEGRATE))) return false;
    if ((m & FixConst::END_OF_STEP) && (!st || st->end_of_step_reads_particles())) fuse_watch.push_back(f);
  }
  return true;
}

/* whether the other fixes leave the atoms' data alone between this fix's initial_integrate and
   the forces: no fix of another kind (the sphcut styles attached to this fix touch none of it) has
   post_integrate, initial_integrate after this one, or pre_force (any; with before_only, one
   before this one).  Without before_only: what a hook after the first half wrote from the atoms'
   data (packed rows) stays valid until the forces (HookCall::kept_to_force; a step with
   reneighbouring, where the atoms may move in the arrays, is the hook owner's to handle) */
template <class DeviceType> bool FixSPHJCThermalKokkos<DeviceType>::others_keep_out(bool before_only) const
{
  int self = -1;
  const auto fixes = sphcut::fix_list(modify);
  for (int i = 0; i < (int) fixes.size(); i++) {
    if (fixes[i] == this) {
      self = i;
      continue;
    }
    if (dynamic_cast<sphcut::AttachedStyle *>(fixes[i])) continue;
    const int m = sphcut::fix_mask(modify, fixes[i]);
    if ((m & FixConst::POST_INTEGRATE) || ((m & FixConst::PRE_FORCE) && (!before_only || self < 0)) ||
        ((m & FixConst::INITIAL_INTEGRATE) && self >= 0))
      return false;
  }
  return true;
}

/* this fix may zero the forces itself (clear_f), in initial_integrate after the half kick and in
   pre_force after a reneighbouring, when that is all LAMMPS' force clear (VerletKokkos::force_clear)
   would do and nothing reads or writes the forces in between: the Verlet integrator, newton off
   (the ghosts' forces are then not cleared either), no kspace or bonded terms (VerletKokkos may
   merge forces computed on the host), no torque or extra force arrays, no neigh_modify include
   group; others_keep_out, where a pre_force after this fix may stay (it comes after pre_force's
   zeroing): a later initial_integrate would read zeroed forces, a post_integrate's forces would
   survive, an earlier pre_force's would be erased after a reneighbouring */
template <class DeviceType> bool FixSPHJCThermalKokkos<DeviceType>::force_clear_allowed() const
{
  if (!utils::strmatch(update->integrate_style, "^verlet") || utils::strmatch(update->integrate_style, "^verlet/split"))
    return false;
  if (force->newton || force->kspace || atom->molecular || atom->torque_flag || atom->avec->forceclearflag ||
      neighbor->includegroup)
    return false;
  return others_keep_out(true);
}

template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::end_of_step()
{
  sphcut::FencedTimer timer(cpu_time);
  // on a dt step (every dtevery-th) the Courant limit and the styles' slots (written by their
  // kernels this step, or by their hooks in this fix's final_integrate) to the host: the step's one
  // host round trip.  Between dt steps none: the plastic work stays on the device (fetch_work)
  if (cfl > 0.0 && dt_step()) {
    fetch_work();
    apply_dt(finish_dt(std::min(k_dtlim.view_host()(STEP_DT), device_limits())));
  }
  // dumps and f_ID outputs read the host array on output steps and every peratom_freq steps
  if (update->ntimestep == output->next || update->ntimestep % peratom_freq == 0) sync_outputs_host();
}

/* the output columns of the local rows to the host (see the header): packed on the device into
   the staging buffer of the classic forward communication (stage_state), one copy, unpacked into
   the host rows.  Within a step nothing changes the state on
   the device after the fixes' final_integrate, so one copy a step serves end_of_step and the
   outputs after it; at a setup it is always made.                                          */
template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::sync_outputs_host()
{
  settle_corrector();
  if (!k_state.need_sync_host()) return;    // the host holds the whole rows
  if (!update->setupflag && outputs_step == update->ntimestep) return;
  const int n = atom->nlocal, nc = NOUT;
  stage_state.pack_range(k_state, 0, nc, 0, n);
  auto hs = k_state.view_host();
  for (int i = 0; i < n; i++)
    for (int c = 0; c < nc; c++) hs(i, c) = stage_state.h_buf(i * nc + c);
  outputs_step = update->setupflag ? -1 : update->ntimestep;
}

template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::post_run()
{
  settle_corrector();    // a run that ended after a deferred step (a timeout)
  report_migration();
  k_state.sync_host();    // the state readable after the run (library interface, tests)
  fetch_work();
  peratom_freq = 1;       // between runs the host copy is current: any consumer (write_dump, ...)
  if (remap && !grow_callback) {
    // between runs the rows follow by index again.  Atom::add_callback only registers the fix
    // being constructed, so the callback goes back into Atom's list here as it would there.
    const int ifix = sphcut::fix_index(modify, this);
    if (atom->nextra_grow == atom->nextra_grow_max) {
      atom->nextra_grow_max += 1;
      memory->grow(atom->extra_grow, atom->nextra_grow_max, "atom:extra_grow");
    }
    atom->extra_grow[atom->nextra_grow++] = ifix;
    std::sort(atom->extra_grow, atom->extra_grow + atom->nextra_grow);
    grow_arrays(atom->nmax);
    grow_callback = 1;
  }
  if (clear_f_active) {
    sphcut::IntegrateForceClear::flag(update->integrate) = saved_force_clear;    // setups and other runs clear as before
    clear_f_active = 0;
  }
  FixSPHJCThermal::post_run();
}

/* the global vector (FixSPHJCThermal::compute_vector): elements 2, 3 (sums over the non-tool
   particles) and 5, 6 (maxima over the group) reduced on the device, so that an output of them
   copies nothing per atom to the host; element 4 is fetch_work's */
template <class DeviceType> double FixSPHJCThermalKokkos<DeviceType>::compute_vector(int n)
{
  settle_corrector();
  if (n == 0) return update->dt;
  if (n == 3) {
    fetch_work();
    return FixSPHJCThermal::compute_vector(n);
  }
  atomKK->sync(execution_space, V_MASK | MASK_MASK | TYPE_MASK | RMASS_MASK);
  k_state.template sync<DeviceType>();
  auto st = k_state.template view<DeviceType>();
  auto v = atomKK->k_v.view<DeviceType>();
  auto mask = atomKK->k_mask.view<DeviceType>();
  auto type = atomKK->k_type.view<DeviceType>();
  auto rmass = atomKK->k_rmass.view<DeviceType>();
  auto mass = atomKK->k_mass.view<DeviceType>();
  const int gb = groupbit, tb = toolbit, cb = clampbit, use_rmass = atom->rmass_flag;
  double loc = 0.0, res = 0.0;
  if (n == 1 || n == 2) {
    const bool kinetic = n == 2;
    Kokkos::parallel_reduce("sphcut:sph:compute_vector_sum", sphcut::range<DeviceType>(0, atom->nlocal),
        KOKKOS_LAMBDA(const int i, double &sum) {
          if (!(mask(i) & gb) || sphcut::role_from_mask(mask(i), tb, cb) == sphcut::StateLayout::TOOL) return;
          const double m = use_rmass ? rmass(i) : mass(type(i));
          sum += kinetic ? 0.5 * m * (v(i, 0) * v(i, 0) + v(i, 1) * v(i, 1) + v(i, 2) * v(i, 2)) : m * st(i, UINT);
        },
        loc);
    MPI_Allreduce(&loc, &res, 1, MPI_DOUBLE, MPI_SUM, world);
    return kinetic ? res * force->mvv2e : res;
  }
  const int col = n == 4 ? TEMP : EPS;
  Kokkos::parallel_reduce("sphcut:sph:compute_vector_max", sphcut::range<DeviceType>(0, atom->nlocal),
      KOKKOS_LAMBDA(const int i, double &mx) {
        if ((mask(i) & gb) && st(i, col) > mx) mx = st(i, col);
      },
      Kokkos::Max<double>(loc));
  loc = std::max(loc, -1.0e300);    // as the CPU fix where no particle of the group is here
  MPI_Allreduce(&loc, &res, 1, MPI_DOUBLE, MPI_MAX, world);
  return res;
}

/* ----------------------------------------------------------------------
   host paths: grow, exchange, sort, restart, classic forward comm.  Each
   syncs the host view first and marks it modified when it writes.
------------------------------------------------------------------------- */

template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::grow_arrays(int nmax)
{
  // Kokkos 3.4 DualView::resize leaves the host mirror unset unless the host is current
  k_state.sync_host();
  k_state.modify_host();
  memoryKK->grow_kokkos(k_state, state, nmax, NCOL, "sph/jc-thermal:state");
  k_state.modify_host();
  array_atom = state;
  k_rowtag.sync_host();
  k_rowtag.modify_host();
  memoryKK->grow_kokkos(k_rowtag, rowtag, nmax, "sph/jc-thermal:rowtag");
  k_rowtag.modify_host();
}

// grow without a host round trip (remap mode: the state is current on the device)
template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::grow_on_device(int n)
{
  k_state.template sync<DeviceType>();
  k_state.template modify<DeviceType>();
  memoryKK->grow_kokkos(k_state, state, n, NCOL, "sph/jc-thermal:state");
  array_atom = state;
  k_rowtag.template sync<DeviceType>();
  k_rowtag.template modify<DeviceType>();
  memoryKK->grow_kokkos(k_rowtag, rowtag, n, "sph/jc-thermal:rowtag");
}

/* ----------------------------------------------------------------------
   remap mode: move the state rows to the atoms' current indices by tag
------------------------------------------------------------------------- */

template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::setup_pre_exchange()
{
  mig.clear();    // the counters of this run
  if (!remap || !grow_callback) return;
  // rows follow the atoms by index until now (grow callback): label them with the tags
  const int nlocal = atom->nlocal;
  atomKK->sync(execution_space, TAG_MASK);
  k_rowtag.template sync<DeviceType>();
  auto tag = atomKK->k_tag.view<DeviceType>();
  auto rt = k_rowtag.template view<DeviceType>();
  Kokkos::parallel_for("sphcut:sph:setup_pre_exchange",
      sphcut::range<DeviceType>(0, nlocal), KOKKOS_LAMBDA(const int i) { rt(i) = tag(i); });
  k_rowtag.template modify<DeviceType>();
  nrows = nlocal;
  atom->delete_callback(id, Atom::GROW);
  grow_callback = 0;
}

template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::setup_post_neighbor()
{
  remap_state();
}

template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::post_neighbor()
{
  sphcut::FencedTimer timer(cpu_time);
  remap_state();
}

template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::remap_state()
{
  if (!remap || grow_callback) return;    // with the callback the rows follow by index
  if ((int) k_state.extent(0) < atom->nmax) grow_on_device(atom->nmax);
  atomKK->sync(execution_space, TAG_MASK);
  nrows = mig.remap(k_state, k_rowtag, nrows, atomKK->k_tag.view<DeviceType>(), atom->nlocal, atom->nmax, world,
                    temp0, error);
}

// several ranks: one line after the timing table's run (rows moved, time, max over ranks)
template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::report_migration()
{
  if (comm->nprocs > 1 && remap && update->nsteps > 0) {
    const bigint loc[3] = {mig.received, mig.sent, mig.created};
    bigint sum[3];
    MPI_Allreduce(loc, sum, 3, MPI_LMP_BIGINT, MPI_SUM, world);
    // the time outside MPI is this rank's own work; the MPI calls include the wait for the
    // slowest rank (load imbalance), not only the transfer
    const double t[2] = {mig.seconds - mig.mpi_seconds, mig.mpi_seconds};
    double tmax[2] = {0.0, 0.0};
    MPI_Allreduce(t, tmax, 2, MPI_DOUBLE, MPI_MAX, world);
    bigint calls = 0;
    MPI_Allreduce(&mig.calls, &calls, 1, MPI_LMP_BIGINT, MPI_MAX, world);
    if (comm->me == 0)
      utils::logmesg(lmp, "sph/jc-thermal/kk migrate device: {} state rows moved between ranks ({} sent, {} new) "
                     "in {} remaps: {:.4g} s on the device and host copies, {:.4g} s in MPI with the wait for the "
                     "slowest rank (max over ranks)\n", sum[0], sum[1], sum[2], calls, tmax[0], tmax[1]);
  }
}

template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::set_arrays(int i)
{
  if (!grow_callback) return;    // during a run (remap mode) remap_state gives new atoms a row
  k_state.sync_host();
  initialize_atom(i);
  k_state.modify_host();
}

template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::copy_arrays(int i, int j, int delflag)
{
  k_state.sync_host();
  FixSPHJCThermal::copy_arrays(i, j, delflag);
  k_state.modify_host();
}

template <class DeviceType> int FixSPHJCThermalKokkos<DeviceType>::pack_exchange(int i, double *buf)
{
  k_state.sync_host();
  return FixSPHJCThermal::pack_exchange(i, buf);
}

template <class DeviceType> int FixSPHJCThermalKokkos<DeviceType>::unpack_exchange(int nlocal, double *buf)
{
  k_state.sync_host();
  const int n = FixSPHJCThermal::unpack_exchange(nlocal, buf);
  k_state.modify_host();
  return n;
}

template <class DeviceType> int FixSPHJCThermalKokkos<DeviceType>::pack_restart(int i, double *buf)
{
  k_state.sync_host();
  return FixSPHJCThermal::pack_restart(i, buf);
}

template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::unpack_restart(int nlocal, int nth)
{
  k_state.sync_host();
  FixSPHJCThermal::unpack_restart(nlocal, nth);
  k_state.modify_host();
}

template <class DeviceType>
int FixSPHJCThermalKokkos<DeviceType>::pack_forward_comm(int n, int *list, double *buf, int, int *)
{
  // the force state of the listed rows, packed on the device (FixSPHJCThermal::pack_forward_comm's
  // columns and order): the state stays on the device
  return stage_state.pack(k_state, FORWARD_FIRST, NFORWARD, n, list, buf);
}

template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::unpack_forward_comm(int n, int first, double *buf)
{
  stage_state.unpack(k_state, FORWARD_FIRST, NFORWARD, n, first, buf);
}

namespace LAMMPS_NS {
template class FixSPHJCThermalKokkos<LMPDeviceType>;
#ifdef LMP_KOKKOS_GPU
template class FixSPHJCThermalKokkos<LMPHostType>;
#endif
}    // namespace LAMMPS_NS
