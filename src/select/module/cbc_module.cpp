// The CBC module's table (select/cbc_module.hpp): CBC's C interface as it is, and ClpSimplex's
// members behind thin wrappers. Nothing here calls back into vantage but through the table's
// arguments.
#include <coin/Cbc_C_Interface.h>
#include <coin/ClpEventHandler.hpp>
#include <coin/ClpSimplex.hpp>

#include <type_traits>

#include "select/cbc_module.hpp"

namespace vantage::detail {

static_assert(std::is_same_v<CoinBigIndex, int>, "the table passes column starts as int");
static_assert(std::is_same_v<Cbc_Model, CbcModelHandle>);

struct ClpHandle {
  ClpSimplex simplex;
};

namespace {

// Stops CLP at the end of an iteration once `stop` says so.
class StopWhen : public ClpEventHandler {
 public:
  explicit StopWhen(bool (*stop)()) : stop_(stop) {}
  int event(Event which) override { return which == endOfIteration && stop_() ? 0 : -1; }
  ClpEventHandler* clone() const override { return new StopWhen(*this); }

 private:
  bool (*stop_)();
};

const CbcModuleApi kApi = {
    kCbcModuleVersion,
    &Cbc_newModel,
    &Cbc_deleteModel,
    &Cbc_loadProblem,
    &Cbc_setInteger,
    &Cbc_setObjSense,
    &Cbc_setLogLevel,
    &Cbc_setParameter,
    &Cbc_setMaximumSeconds,
    &Cbc_setAllowableGap,
    &Cbc_setAllowableFractionGap,
    &Cbc_setMIPStartI,
    &Cbc_solve,
    &Cbc_getBestPossibleObjValue,
    &Cbc_isProvenOptimal,
    &Cbc_status,
    &Cbc_secondaryStatus,
    [](CbcModelHandle* model) -> const double* { return Cbc_bestSolution(model); },
    [](int columns, int rows, const int* starts, const int* indices, const double* values,
       const double* column_lower, const double* column_upper, const double* objective,
       const double* row_lower, const double* row_upper) {
      auto* model = new ClpHandle;
      model->simplex.setLogLevel(0);
      model->simplex.loadProblem(columns, rows, starts, indices, values, column_lower,
                                 column_upper, objective, row_lower, row_upper);
      return model;
    },
    [](ClpHandle* model) { delete model; },
    [](const ClpHandle* model) { return model->simplex.numberColumns(); },
    [](const ClpHandle* model, const double* x, double* y) {
      model->simplex.matrix()->times(x, y);
    },
    [](const ClpHandle* model) -> const double* { return model->simplex.rowLower(); },
    [](ClpHandle* model) { return model->simplex.primalColumnSolution(); },
    [](const ClpHandle* model) -> const double* { return model->simplex.dualRowSolution(); },
    [](ClpHandle* model, double seconds) { model->simplex.setMaximumSeconds(seconds); },
    [](ClpHandle* model, double seconds) { model->simplex.setMaximumWallSeconds(seconds); },
    [](ClpHandle* model, bool (*stop)()) {
      StopWhen handler(stop);
      model->simplex.passInEventHandler(&handler);  // CLP keeps a copy
    },
    [](ClpHandle* model, int values_pass) { return model->simplex.primal(values_pass); },
    [](ClpHandle* model) { return model->simplex.dual(); },
    [](const ClpHandle* model) { return model->simplex.status(); },
    [](const ClpHandle* model) { return model->simplex.objectiveValue(); },
    [](const ClpHandle* model) { return model->simplex.numberIterations(); },
};

}  // namespace
}  // namespace vantage::detail

extern "C" __attribute__((visibility("default"))) const vantage::detail::CbcModuleApi*
vantage_cbc_module() {
  return &vantage::detail::kApi;
}
