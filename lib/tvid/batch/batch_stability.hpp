#pragma once
// How stable the identified model is from job to job: each free parameter's spread over
// the successful jobs (mean, standard deviation, coefficient of variation, median, MAD),
// and the jobs that stand out by a robust z-score (robust_statistics.hpp) on a parameter
// or, with the cross-cycle matrix, on their mean fit on the other jobs' data.
// Written to batch_summary.json and parameter_stability.csv.

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tvid/batch/batch_table.hpp"
#include "tvid/batch/cross_matrix.hpp"
#include "tvid/batch/robust_statistics.hpp"

namespace tvid {

struct ParameterStability {
    std::string name, unit;
    Stability stats;
};

/// A job flagged by |robust z| > kOutlierRobustZ on one quantity (judged only over at
/// least kOutlierMinimumJobs jobs with a value).
struct OutlierJob {
    std::string id;
    std::string subject;   ///< the parameter's name, or "mean_cross_fit"
    double value = 0.0, median = 0.0, mad = 0.0, z = 0.0;
    std::string reason;    ///< one line: the value, its z-score, the median and MAD
};

struct BatchStability {
    std::vector<ParameterStability> parameters;  ///< per free parameter, in column order
    std::vector<OutlierJob> outliers;            ///< in job order, then parameters, then the cross fit
};

/// Over the rows with status ok; `units` per free parameter ("" when unknown); `cross`
/// (may be null) adds the mean cross-validation fit as a quantity to judge.
BatchStability batch_stability(const BatchColumns& columns, const std::vector<BatchRow>& rows,
                               const std::vector<std::string>& units, const CrossMatrix* cross);

/// parameter_stability.csv: `parameter,unit,count,mean,std,cv,median,mad,min,max,outliers`.
std::string parameter_stability_csv(const BatchStability& stability);

/// batch_summary.json's `parameter_stability` (by parameter) and `outliers` (a list).
nlohmann::json parameter_stability_json(const BatchStability& stability);
nlohmann::json outliers_json(const BatchStability& stability);

/// batch_summary.json's `cross`: the matrix's files, jobs, outputs, and each job's own and
/// mean cross-validation fit.
nlohmann::json cross_matrix_json(const CrossMatrix& matrix);

}  // namespace tvid
