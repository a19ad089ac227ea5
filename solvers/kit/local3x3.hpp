// One-contact solvers, which NSGS calls for each contact (ids 552, 553 and 562 of
// frix_options.h); the projections and the residual they use are the core's (coulomb.hpp).
// Vectors are per contact, normal first; 3x3 matrices are column-major.
#pragma once

#include <cmath>
#include <cstdint>

namespace frix::local {

// Per-contact data computed once per solve from the diagonal block W_aa.
struct Contact {
    double W[9];     // W_aa
    double Winv[9];  // W_aa^-1, valid only if has_inverse
    double mu;
    double rho;       // step of the projected iterations; 553 adapts it across sweeps
    double rho0;      // 1 / |W_aa|_2: the fixed step of 552 and the reset value of rho
    double dir[2];    // unit sliding direction of the last Slide outcome, if has_dir
    bool has_dir;
    bool has_inverse;
    bool degenerate;  // W_aa is (numerically) zero: no local solution exists when q_N < 0
};

void contact_setup(const double *Waa, double mu, Contact &c);

enum class Outcome : int {
    TakeOff = 1,       // q_N >= 0: r = 0
    Stick = 2,         // r = -W^-1 q inside the cone: u = 0
    Slide = 3,         // exact sliding solution on the cone boundary (root of the angle equation)
    Iterated = 4,      // projected iterations reached the local tolerance
    NotConverged = 5,  // projected iterations stopped at the local iteration limit
    NoSolution = 6,    // degenerate W_aa with q_N < 0: r left unchanged
    Step = 7,          // one projected step (552)
    Newton = 8         // a one-contact Newton (550, 551, 561, 565) reached the local tolerance
};

constexpr int kProjection = 552;          // FRIX_LOCAL_PROJECTION
constexpr int kProjectionIterated = 553;  // FRIX_LOCAL_PROJECTION_ITERATED
constexpr int kClosedForm = 562;          // FRIX_LOCAL_CLOSED_FORM

struct Params {
    int solver = kClosedForm;
    double tol = 1e-12;  // on the one-contact residual, relative to max(|q|, |r|, |u|)
    int max_iter = 20;   // of the projected iterations (553, and 562's fallback)
};

// G(theta) = A0 + A1 cos + B1 sin + A2 cos 2theta + B2 sin 2theta, evaluated at the unit vector
// (c, s) = (cos theta, sin theta): the form to which the boundary case of both one-contact
// problems reduces (De Saxce sliding here, the second-order cone one in fixed_points.cpp).
struct TrigPoly2 {
    double A0 = 0, A1 = 0, B1 = 0, A2 = 0, B2 = 0, scale = 0;
    void set_scale() {
        scale = std::fabs(A0) + std::fabs(A1) + std::fabs(B1) + std::fabs(A2) + std::fabs(B2);
    }
    double value(double c, double s) const {
        return A0 + A1 * c + B1 * s + A2 * (c * c - s * s) + 2.0 * B2 * c * s;
    }
    double derivative(double c, double s) const {
        return -A1 * s + B1 * c - 4.0 * A2 * c * s + 2.0 * B2 * (c * c - s * s);
    }
};

// Turns a root direction (c, s) into a reaction r (3) if it is a valid solution.
using ReactionFn = bool (*)(const double *W, const double *q, double mu, double c, double s,
                            double *r);

// The root of g whose reaction is valid and whose direction is nearest the unit vector
// (hc, hs): Newton from (hc, hs), else every sign change on a 32-point grid bracketed and
// polished. dir (2) receives the root's direction. False if no valid root exists.
bool nearest_valid_root(const TrigPoly2 &g, const double *W, const double *q, double mu,
                        ReactionFn reaction, double hc, double hs, double *r, double *dir);

// Solves the one-contact problem u = W_aa r + q, K ∋ r ⟂ u + mu|u_T| e_N ∈ K*.
// r holds the current reaction on entry (warm start) and the new one on return; it is
// unchanged when the outcome is NoSolution.
Outcome solve_contact(Contact &c, const double *q, double *r, const Params &p);

// The sliding root alone (exposed for tests): true and r set if a valid sliding solution
// was found. `hint` (3, may be null) selects among several roots.
bool solve_slide(const Contact &c, const double *q, const double *hint, double *r);

}  // namespace frix::local
