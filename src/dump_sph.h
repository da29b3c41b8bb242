/* -*- c++ -*- ----------------------------------------------------------
   sphcut - command dump_sph: a dump custom of the SPH state under readable
   column names (density, pressure, sxx, ..., temperature, surface, ...),
   so OVITO / ParaView show named particle properties instead of f_ID[k]
------------------------------------------------------------------------- */

#ifdef COMMAND_CLASS
// clang-format off
CommandStyle(dump_sph,DumpSPH);
// clang-format on
#else

#ifndef LMP_DUMP_SPH_H
#define LMP_DUMP_SPH_H

#include "command.h"

#include <string>
#include <vector>

namespace LAMMPS_NS {

class DumpSPH : public Command {
 public:
  DumpSPH(class LAMMPS *lmp) : Command(lmp) {}
  void command(int, char **) override;

  // the sphcut field names and where they come from: 0 fix sph/jc-thermal,
  // 1 compute surface/lambda, 2 fix contact/tri-penalty; column (1-based)
  struct Field {
    const char *name;
    int source;
    int column;
  };
  static const std::vector<Field> &fields();
};

}    // namespace LAMMPS_NS

#endif
#endif
