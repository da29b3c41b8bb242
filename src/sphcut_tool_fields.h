/* -*- c++ -*- ----------------------------------------------------------
   sphcut - tool fields per facet for fix contact/tri-penalty (keywords
   tool_fields N, wear usui K alpha): the host side of the contact's
   per-facet loads and Usui wear.  The per-contact arithmetic is in
   sphcut_contact.h (facet_scatter, facet_contact_sums, usui_rate), used by
   the CPU and /kk drivers; this class holds the per-facet sums of the
   running averaging interval (this rank), closes an interval (MPI sum,
   averages, accumulated wear depth, global sums), and packs the state for
   restart files.  Host only.
------------------------------------------------------------------------- */

#ifndef SPHCUT_TOOL_FIELDS_H
#define SPHCUT_TOOL_FIELDS_H

#include "sphcut_contact.h"

#include <mpi.h>
#include <string>
#include <vector>

namespace sphcut {

class ToolFields {
 public:
  // output columns per facet (fix array f_ID[facet][column], 1-based for the user)
  enum {
    C_SN = 0,    // normal stress, time average of sum F_N / A
    C_TAU,       // shear stress, time average of sum |F_T| / A
    C_VS,        // sliding speed, mean over the contacts (and time)
    C_T,         // temperature of the particles in contact, mean over the contacts (and time)
    C_N,         // contacts, time average (an edge / vertex contact counts 1/n on each of its n facets)
    C_WEAR,      // Usui wear rate dW/dt, time average
    C_DEPTH,     // accumulated wear depth W (closed intervals)
    C_FX, C_FY, C_FZ,    // force on the tool, time average
    C_AREA,      // facet area (2D: segment length)
    C_FEAT,      // 1 rake, 2 edge, 3 flank, 4 other
    C_CX, C_CY, C_CZ,    // centroid (the tool's position at the interval's end)
    NCOL
  };
  // global sums (fix vector, appended after the existing elements)
  enum { G_WEAR_RATE = 0, G_FN, G_FT, G_WEAR_VOL, G_DEPTH_MAX, NGLOB };

  int every = 0;                  // averaging interval in steps (0: off)
  int wear = 0;                   // 1: wear usui given
  double K = 0.0, alpha = 0.0;    // Usui constants (0 0 without wear: the rate column stays 0)
  int nvert = 3, nfacet = 0;
  std::vector<double> area, inv_area;
  std::vector<int> feature;       // C_FEAT values
  std::vector<int> share_start, share_elem;    // FacetShare (sphcut_contact.h)
  std::vector<double> acc;        // NFS per facet: this rank's dt-weighted sums of the running interval
  double time = 0.0;              // sum of dt over the running interval (the same on all ranks)
  std::vector<double> depth;      // accumulated wear depth per facet, closed intervals (all ranks)
  std::vector<double> out;        // NCOL per facet: the last closed interval (all ranks)
  double glob[NGLOB] = {0.0, 0.0, 0.0, 0.0, 0.0};

  // areas, features (1..4), the facets sharing each edge / vertex (exactly equal coordinates)
  void build(const std::vector<double> &elem, int nvert, const std::vector<int> &feat);
  FacetShare share() const;
  void add(int f, const double *c)
  {
    double *a = &acc[(size_t) f * NFS];
    for (int k = 0; k < NFS; k++) a[k] += c[k];
  }
  // MPI sum of the running interval, its averages into out and glob, wear depth; restart the sums.
  // cur_elem: the current (moved) elements for the centroids
  void close_interval(MPI_Comm world, const std::vector<double> &cur_elem);
  // the centroid columns of out from the current elements (close_interval; a run's setup where
  // no interval closes: fix contact/tri-penalty fields_at_setup)
  void set_pose(const std::vector<double> &cur_elem);
  static const char *column_name(int c);
  // the VTK cell arrays of write_vtk: every column's name (none while the tool fields are off)
  std::vector<std::string> vtk_names() const;
  // restart block: [nfacet, time, depth (nfacet), acc summed over the ranks (nfacet NFS), out
  // (nfacet NCOL), glob (NGLOB)]; collective
  std::vector<double> restart_data(MPI_Comm world) const;
  static size_t restart_size(int nfacet) { return 2 + (size_t) nfacet * (1 + NFS + NCOL) + NGLOB; }
  // from a block of restart_data; the rank sums go to rank 0 (me0). Returns false if nfacet differs.
  bool read_restart(const double *buf, bool me0);
};

}    // namespace sphcut

#endif
