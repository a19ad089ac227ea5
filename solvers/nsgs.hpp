// Nonsmooth Gauss-Seidel (id 500): sweeps over the contacts of a local problem, each solved
// exactly or nearly so by a one-contact solver of local3x3.hpp.
#pragma once

#include <cstdint>
#include <vector>

#include "local3x3.hpp"
#include "problem.hpp"
#include "solver_api.hpp"

namespace frix {

extern const SolverEntry kNsgsEntry;

namespace nsgs {

struct Settings {
    local::Params local;
    double relaxation = 1.0;
    int shuffle = 0;  // frix_shuffle
    uint64_t seed = 0;
};

// The sweep settings an options object (of solver 500) asks for.
Settings settings_from(const frix_options &o);

struct SweepStats {
    double dr2 = 0.0;        // sum over contacts of |r_a,new - r_a,old|^2
    double r2 = 0.0;         // |r|^2 after the sweep
    int64_t rejected = 0;    // non-finite local results discarded
    int64_t unsolved = 0;    // local solves that stopped short of the local tolerance
};

// Everything a sweep needs, prepared once per solve; sweeps allocate nothing.
class Workspace {
   public:
    Workspace(const frix_problem &p, const Settings &s);
    // One pass over the contacts, updating r in place.
    SweepStats sweep(double *r);

   private:
    const frix_matrix &W_;
    const double *q_;
    Settings s_;
    std::vector<local::Contact> contacts_;
    std::vector<int64_t> order_;
    uint64_t rng_;
};

}  // namespace nsgs
}  // namespace frix
