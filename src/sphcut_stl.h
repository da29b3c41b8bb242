/* -*- c++ -*- ----------------------------------------------------------
   sphcut - host utilities for rigid tool geometry (plain C++14, no
   LAMMPS): STL reading/writing, a legacy VTK writer, the orthogonal
   cutting insert generator and the build of the contact bins
   (TriBinView of sphcut_contact.h).

   Element arrays are flat std::vector<double>: 9 doubles per triangle
   (a, b, c; outward normal by the right-hand rule, eq. 7 of seed 000),
   6 per 2D segment (a, b with z = 0; outward normal (dy, -dx), i.e. a
   closed outline runs counter-clockwise).

   Errors: std::runtime_error (std::invalid_argument for bad parameters)
   with a one-line message naming the file and the problem.
------------------------------------------------------------------------- */

#ifndef SPHCUT_STL_H
#define SPHCUT_STL_H

#include "sphcut_contact.h"

#include <string>
#include <vector>

namespace sphcut {

/* ----------------------------------------------------------------------
   placement of a mesh read from file: x' = R (scale x) + shift.
   Angles in degrees.  Default: identity.
     set_axis_angle(axis, angle): right-handed rotation about axis
       (any length > 0) through the origin of the file frame.
     set_euler_zyx(az, ay, ax): R = Rz(az) Ry(ay) Rx(ax), i.e. rotate
       about the fixed x axis first, then y, then z (equivalently z, y', x''
       about the moving axes).
   scale must be > 0 (a mirror would flip the facet winding).
------------------------------------------------------------------------- */

struct StlTransform {
  double scale = 1.0;
  double shift[3] = {0.0, 0.0, 0.0};
  double rot[9] = {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0};    // row major
  void set_axis_angle(const double *axis, double angle_deg);
  void set_euler_zyx(double az_deg, double ay_deg, double ax_deg);
  void apply(const double *x, double *y) const;
};

/* ----------------------------------------------------------------------
   read an ASCII or binary STL (auto-detected: a file is binary when its
   size is 84 + 50 N with N the facet count of the binary header, even if
   it starts with "solid" as many CAD exporters write; else ASCII when it
   starts with "solid" and holds no NUL/control bytes; else binary).
   Returns 9 doubles per facet after the transform.  Checks (throw):
   missing/unreadable or empty file, no facets, truncated binary,
   malformed ASCII (line number given), a degenerate (zero area) facet,
   as read and after the transform (twice its area at most 1e-12 of its
   longest edge squared, or its longest edge at most 1e-9 of the largest
   coordinate of the facet: below the resolution of the coordinates, e.g.
   scale 1e-30 with a shift; the message names the facet and the scale),
   and a stored normal (non-zero) that disagrees with the vertex winding
   (dot < 0; facet index given, facets count from 0).
------------------------------------------------------------------------- */

std::vector<double> read_stl(const std::string &file, const StlTransform &tf = StlTransform());

// path names a directory (std::ifstream opens one on Linux and reads nothing from it)
bool is_directory(const std::string &path);

/* ----------------------------------------------------------------------
   closed-surface check of a triangle mesh.  Vertices are matched exactly
   (an STL repeats the vertices of each facet with the same coordinates).
   The surface of a solid uses every edge equally often in both directions
   (each facet runs counter-clockwise seen from outside).  open_edges:
   edges of one facet only (the border of an open sheet or of a hole);
   inconsistent_edges: other edges used unequally often in the two
   directions (a facet turned inside out).  edge: one offending edge (a, b).
------------------------------------------------------------------------- */

struct MeshClosure {
  long open_edges = 0;
  long inconsistent_edges = 0;
  double edge[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  bool closed() const { return open_edges == 0 && inconsistent_edges == 0; }
};

MeshClosure mesh_closure(const std::vector<double> &tri);

// the volume a closed triangle mesh encloses, sum over facets of a.(b x c)/6 (about its first
// vertex): > 0 with outward normals, < 0 when every facet is turned inward
double mesh_volume(const std::vector<double> &tri);

// throws std::runtime_error ("STL file '...': the mesh is not closed: ...") unless closed, and
// unless it encloses a positive volume ("... negative volume ...: its facet normals point
// inward", or "encloses no volume" when |V| <= 1e-12 of its bounding-box diagonal cubed)
void require_closed_mesh(const std::string &file, const std::vector<double> &tri);

// the 2D tool of an STL solid: its section with the plane z = 0, one segment (6 doubles, z = 0)
// per facet that crosses it (a vertex at z = 0 counts as above), oriented by the facet normal
// (outward normal (dy, -dx)).  The crossing point of a mesh edge is computed from its end
// points in a fixed order, so the segments of neighbouring facets meet at bitwise equal points
// (the vertex pseudo-normals of tri_bin_build find them); segments of zero length are dropped.
// Throws ("STL file '...': no facet crosses the plane z = 0 ...") when the section is empty.
std::vector<double> stl_section_z0(const std::string &file, const std::vector<double> &tri);

// the bounding box of a vertex array (3 doubles per vertex: elements of any kind; all 0 if empty),
// the diagonal of a box and of the array's bounding box
void bounding_box(const std::vector<double> &pts, double *lo, double *hi);
double box_diagonal(const double *lo, const double *hi);
double bounding_diagonal(const std::vector<double> &pts);

// ASCII STL, coordinates with 17 significant digits (exact round trip)
void write_stl_ascii(const std::string &file, const std::vector<double> &tri,
                     const std::string &name = "sphcut");

// binary STL (float32, little endian); header text is padded to 80 bytes
void write_stl_binary(const std::string &file, const std::vector<double> &tri,
                      const std::string &header = "sphcut binary STL");

// legacy VTK unstructured grid (ParaView, OVITO, meshio): nvert 3 = triangles with cell
// normals, nvert 2 = 2D segments as lines
// cell_names / cell_values (optional): scalar cell arrays after the normals, cell_values row by
// row (one row of cell_names.size() values per element)
void write_vtk(const std::string &file, const std::vector<double> &elem, int nvert = 3,
               const std::vector<std::string> &cell_names = {}, const std::vector<double> &cell_values = {});

/* ----------------------------------------------------------------------
   orthogonal cutting insert.  Convention (x-y is the cutting plane):
   - the tool cuts in -x (moves towards -x); the chip flows up (+y) along
     the rake face, the machined surface lies below (y < 0 side).
   - rake face: faces -x, tilted by gamma from the +y axis; positive gamma
     tilts it away from the chip (it leans back towards +x going up):
     direction up the face (sin g, cos g), outward normal (-cos g, sin g).
   - flank face: faces -y, tilted by alpha from the -x direction so that
     it rises behind the edge: direction (cos a, sin a) away from the edge,
     outward normal (sin a, -cos a).  Wedge angle 90 - alpha - gamma > 0.
   - cutting edge: circular arc of radius r_beta tangent to both faces,
     centre (0, r_beta), split into arc_segments chords (vertices on the
     arc; the split puts a vertex at the lowest point); its lowest point,
     the tool tip, is at the origin.  r_beta = 0: sharp edge at the origin.
   - rake_length / flank_length: face lengths from the arc tangent points.
   - face_segments: the rake and flank faces split into this many equal
     parts (1: one element each; more give tool fields along the faces).
   - one back face joins the free ends of the rake and flank faces (the
     section is a convex polygon).
   dim 3: extruded over z in [-width/2, width/2], closed triangle mesh
     with outward normals (end caps fan-triangulated).
   dim 2: the closed section as counter-clockwise segments (6 doubles).
   tags (optional): per element one of the InsertFace values.
------------------------------------------------------------------------- */

struct InsertParams {
  double rake_angle = 0.0;         // gamma [deg]
  double clearance_angle = 7.0;    // alpha [deg]
  double edge_radius = 0.0;        // r_beta
  double rake_length = 1.0;
  double flank_length = 1.0;
  double width = 1.0;              // dim 3 only
  int arc_segments = 8;            // >= 1 (2 when the tip splits the arc)
  int face_segments = 1;           // >= 1: rake and flank faces each split into this many equal parts
  double land = 0.0;               // >= 0: a flank wear land, a flat of this width at the tip's height
                                   // (zero clearance) between the tip and the flank (tagged flank)
};

enum InsertFace { INSERT_RAKE = 0, INSERT_EDGE = 1, INSERT_FLANK = 2, INSERT_BACK = 3, INSERT_SIDE = 4 };

std::vector<double> make_cutting_insert(const InsertParams &p, int dim,
                                        std::vector<int> *tags = nullptr);

/* ----------------------------------------------------------------------
   contact bins (host build, see TriBinView in sphcut_contact.h).  bin_size
   is typically the contact cutoff: each bin lists the elements within the
   bin size (halo) of it, and the grid holds one bin more on each side of
   the elements' box, so that a query of radius <= bin_size reads the one
   bin holding the point; the bins are enlarged (halo with them) when the
   grid would exceed max_bins.  The
   elements are copied (segment z set to 0), and the pseudo-normals of
   their features are computed (pseudo_normals).  view() points into this
   object: rebuild the view after moving or copying it.
------------------------------------------------------------------------- */

struct TriBins {
  int nvert = 3;
  std::vector<double> elem, sphere;
  std::vector<double> pnorm;    // pseudo_normals(elem, nvert)
  std::vector<int> start, index;
  double lo[3] = {0.0, 0.0, 0.0};
  double size = 0.0;
  int n[3] = {0, 0, 0};
  double halo = 0.0;                                    // TriBinView::halo
  double box_lo[3] = {0.0, 0.0, 0.0}, box_hi[3] = {0.0, 0.0, 0.0};    // the elements' bounding box
  TriBinView view() const;
};

void tri_bin_build(const std::vector<double> &elem, int nvert, double bin_size, TriBins &bins,
                   long max_bins = 1L << 24);

/* ----------------------------------------------------------------------
   angle-weighted pseudo-normals (Baerentzen and Aanaes, IEEE TVCG 11,
   2005) of the features of every element, unit vectors, in the layout
   of TriBinView::pnorm: per triangle 6 (edges AB BC CA, vertices A B C),
   per segment 2 (vertices A B).  Vertices are matched by their exact
   coordinates (as mesh_closure).
     edge: the sum of the normals of its two facets;
     vertex: the sum of the normals of its facets, each weighted by the
       facet's angle at the vertex;
     2D vertex: the sum of the normals of its two segments.
   The sign of (p - q) against it tells inside from outside for the
   closest point q on that feature of a closed mesh, whatever the angle.
   Where the mesh is not a closed manifold there (an edge not used by
   exactly two facets in opposite directions: the border of an open
   sheet, a non-manifold or inconsistent edge; a vertex on such an edge;
   a 2D vertex not joining exactly one incoming and one outgoing segment)
   and where the sum vanishes (a zero-thickness fin), the feature takes
   the element's own face normal: the side rule of the face, as before
   pseudo-normals (right for open sheets away from sharp features).
------------------------------------------------------------------------- */

std::vector<double> pseudo_normals(const std::vector<double> &elem, int nvert);

/* ----------------------------------------------------------------------
   signed distance of x (tool frame) to the surface of a closed tool, < 0
   inside, from its closest element with the sign rule of the contact
   (tri_bin_contact_normal, closed solid: pseudo-normals at edges and
   vertices).  The bins are searched within r0, then
   2 r0, 4 r0, ... (a point deep inside still finds the surface); a point
   outside the bins' box is outside: HUGE_VAL.
------------------------------------------------------------------------- */

double tool_signed_distance(const TriBins &bins, const double *x, double r0);

}    // namespace sphcut

#endif
