#pragma once
/// The CBC module (issue 47): CBC and CLP (libCbcSolver, Cbc, Cgl, Osi, Clp, CoinUtils and their
/// lapack, blas and gfortran) are a shared module of their own, libvantage_cbc.so, loaded the
/// first time a model is solved: their libraries cost every process start about 8 ms, and most
/// runs never solve a MILP or an LP. milp.cpp, cbc_answer.cpp (CBC's C interface), lp_bound.cpp
/// and set_cover_search.cpp (ClpSimplex) call CBC and CLP through this table of thin wrappers:
/// plain types only, so that nothing here needs CBC's headers.
#include <cstdint>

namespace vantage::detail {

/// Bumped whenever the table changes: a module from another build is refused.
inline constexpr int kCbcModuleVersion = 1;

/// CBC's Cbc_Model (a void in its C interface) and a ClpSimplex, opaque.
using CbcModelHandle = void;
struct ClpHandle;

struct CbcModuleApi {
  int version = kCbcModuleVersion;
  // CBC's C interface (coin/Cbc_C_Interface.h), one entry per function called; column starts
  // are CoinBigIndex, which is int in Debian's CoinUtils (the module checks).
  CbcModelHandle* (*cbc_new_model)();
  void (*cbc_delete_model)(CbcModelHandle* model);
  void (*cbc_load_problem)(CbcModelHandle* model, int columns, int rows, const int* starts,
                           const int* indices, const double* values, const double* column_lower,
                           const double* column_upper, const double* objective,
                           const double* row_lower, const double* row_upper);
  void (*cbc_set_integer)(CbcModelHandle* model, int column);
  void (*cbc_set_obj_sense)(CbcModelHandle* model, double sense);
  void (*cbc_set_log_level)(CbcModelHandle* model, int level);
  void (*cbc_set_parameter)(CbcModelHandle* model, const char* name, const char* value);
  void (*cbc_set_maximum_seconds)(CbcModelHandle* model, double seconds);
  void (*cbc_set_allowable_gap)(CbcModelHandle* model, double gap);
  void (*cbc_set_allowable_fraction_gap)(CbcModelHandle* model, double gap);
  void (*cbc_set_mip_start_i)(CbcModelHandle* model, int count, const int* columns,
                              const double* values);
  int (*cbc_solve)(CbcModelHandle* model);
  double (*cbc_best_possible_obj_value)(CbcModelHandle* model);
  int (*cbc_is_proven_optimal)(CbcModelHandle* model);
  int (*cbc_status)(CbcModelHandle* model);
  int (*cbc_secondary_status)(CbcModelHandle* model);
  const double* (*cbc_best_solution)(CbcModelHandle* model);

  // A ClpSimplex (coin/ClpSimplex.hpp): made with log level 0 and the problem loaded
  // (loadProblem's arguments), then its members of the same names.
  ClpHandle* (*clp_new)(int columns, int rows, const int* starts, const int* indices,
                       const double* values, const double* column_lower,
                       const double* column_upper, const double* objective,
                       const double* row_lower, const double* row_upper);
  void (*clp_delete)(ClpHandle* model);
  int (*clp_number_columns)(const ClpHandle* model);
  /// matrix()->times(x, y): y += A x.
  void (*clp_times)(const ClpHandle* model, const double* x, double* y);
  const double* (*clp_row_lower)(const ClpHandle* model);
  double* (*clp_primal_column_solution)(ClpHandle* model);
  const double* (*clp_dual_row_solution)(const ClpHandle* model);
  void (*clp_set_maximum_seconds)(ClpHandle* model, double seconds);
  void (*clp_set_maximum_wall_seconds)(ClpHandle* model, double seconds);
  /// Passes in an event handler that stops CLP at the end of an iteration once `stop` returns
  /// true (CLP keeps a copy).
  void (*clp_stop_when)(ClpHandle* model, bool (*stop)());
  int (*clp_primal)(ClpHandle* model, int values_pass);
  int (*clp_dual)(ClpHandle* model);
  int (*clp_status)(const ClpHandle* model);
  double (*clp_objective_value)(const ClpHandle* model);
  int (*clp_number_iterations)(const ClpHandle* model);
};

/// The module's table, loaded on the first call (thread-safe, never unloaded). Throws
/// InternalError naming the places looked at when the module is not installed.
const CbcModuleApi& Cbc();

}  // namespace vantage::detail

/// The module's one exported symbol.
extern "C" const vantage::detail::CbcModuleApi* vantage_cbc_module();
