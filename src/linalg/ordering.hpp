// The symbolic analysis every SparseCholesky and cholesky_cost runs (CHOLMOD, "l" interface).
#pragma once

#include <cholmod.h>

#include "linalg.hpp"

namespace frix::linalg {

// A non-owning cholmod_sparse header over A (CHOLMOD only reads it): its pattern alone where A
// has no values.
cholmod_sparse view_of(const CscView &A, int stype);

// Analyses the symmetric matrix a (CHOLMOD reads its upper triangle) as CHOLMOD's default
// does: AMD, and where AMD's factor has many flops per entry (CHOLMOD's own test, a mesh-like
// pattern) and too many for METIS's own time to be small beside it, METIS's nested dissection
// too, keeping the ordering with the fewer entries of L (CHOLMOD's rule). METIS runs on the
// graph of a's column groups (consecutive columns of nearly the same pattern: the dofs of one
// node of a mesh) instead of a's own: a vertex per node instead of per dof, ordered several
// times faster, each group's columns then numbered together, as an ordering of a mesh numbers
// them anyway. c's ordering settings are used and restored; c.fl and c.lnz are those of the
// ordering returned. The caller holds metis_mutex(). Null where CHOLMOD fails (c.status says
// why). Orderings::kAmdOnly: AMD's analysis alone.
cholmod_factor *analyze_symmetric(cholmod_sparse &a, cholmod_common &c,
                                  Orderings orderings = Orderings::kAmdOrNested);

}  // namespace frix::linalg
