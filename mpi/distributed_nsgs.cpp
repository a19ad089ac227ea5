// Distributed NSGS (frix_mpi_solve): the serial nsgs iteration (run_sweeps: its stopping
// rule, freezing, limits and callback) on a sweep and measures that span the ranks.
//
// A sweep is one Gauss-Seidel pass over all contacts in a fixed order. Ranks are coloured
// so that neighbours differ (distributed_problem.cpp); the order is: the boundary contacts
// of the ranks of colour 0, then of colour 1, ..., with each rank's interior contacts (coupled
// to its own contacts only) anywhere in between. A rank of colour 0 sweeps its boundary, sends
// it, then sweeps its interior; a rank of a higher colour sweeps its interior while its lower
// neighbours' reactions travel, then its boundary, then sends. Each rank ends a sweep with
// every ghost current, which the measures and the next sweep read.
#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "mpi/distributed.hpp"
#include "solvers/nsgs.hpp"
#include "src/error_state.hpp"
#include "src/measures.hpp"
#include "src/solver_api.hpp"

namespace frix {
namespace mpi {
namespace {

constexpr int kTag = 5003;  // reactions of boundary contacts (one message per pair a sweep)

// |x|_2 over the ranks' parts of x (norm2's arithmetic: plain sums, rescaled out of range).
double norm2_all(MPI_Comm comm, const double *x, int64_t n) {
    double s = 0.0;
    for (int64_t i = 0; i < n; ++i) s += x[i] * x[i];
    const std::vector<double> sums = gather_all(comm, &s, 1);
    double all = sums[0];
    for (size_t k = 1; k < sums.size(); ++k) all += sums[k];
    if (in_safe_range(all)) return std::sqrt(all);
    const double mine = max_abs(x, n);
    const std::vector<double> maxima = gather_all(comm, &mine, 1);
    const double a = *std::max_element(maxima.begin(), maxima.end());
    if (a == 0.0) return 0.0;
    s = 0.0;
    for (int64_t i = 0; i < n; ++i) s += (x[i] / a) * (x[i] / a);
    const std::vector<double> scaled = gather_all(comm, &s, 1);
    all = scaled[0];
    for (size_t k = 1; k < scaled.size(); ++k) all += scaled[k];
    return a * std::sqrt(all);
}

// measures_from_parts' rescue over the ranks' contacts.
class RanksRescue : public MeasureRescue {
   public:
    RanksRescue(MPI_Comm comm, const double *r, const double *u, const double *mu, int64_t nc)
        : comm_(comm), r_(r), u_(u), mu_(mu), nc_(nc) {}
    double max_abs_ru() override {
        const double mine = std::max(max_abs(r_, 3 * nc_), max_abs(u_, 3 * nc_));
        const std::vector<double> all = gather_all(comm_, &mine, 1);
        return *std::max_element(all.begin(), all.end());
    }
    void residual(double divisor, double &sum, double &cone) override {
        double mine[2];
        rescaled_residual(r_, u_, mu_, 0, nc_, divisor, mine[0], mine[1]);
        const std::vector<double> all = gather_all(comm_, mine, 2);
        sum = all[0];
        cone = all[1];
        for (size_t k = 1; 2 * k < all.size(); ++k) {
            sum += all[2 * k];
            cone = std::max(cone, all[2 * k + 1]);
        }
    }
    double norm_r() override { return norm2_all(comm_, r_, 3 * nc_); }
    double norm_u() override { return norm2_all(comm_, u_, 3 * nc_); }

   private:
    MPI_Comm comm_;
    const double *r_, *u_, *mu_;
    int64_t nc_;
};

// The sweep and the measures over the ranks. r holds the owned reactions, then the ghosts'.
class DistributedRows : public nsgs::SweepForm {
   public:
    explicit DistributedRows(const frix_mpi_problem &p)
        : p_(p), comm_(p.ctx->comm), norm_q_(norm2_all(comm_, p.scale(), 3 * p.owned)) {
        const size_t n = p.neighbours.size();
        send_buffer_.resize(3 * p.send.size());
        requests_.reserve(2 * n);
        for (size_t k = 0; k < n; ++k) (p.neighbour_colour[k] < p.colour ? lower_ : higher_).push_back(k);
    }

    nsgs::SweepStats sweep(nsgs::Workspace &ws, double *r, double *) override {
        requests_.clear();
        receive(lower_, r);
        const std::vector<int64_t> &b = p_.boundary, &in = p_.interior;
        nsgs::SweepStats st;
        if (p_.colour == 0) {
            st = ws.sweep_part(r, b.data(), (int64_t)b.size());
            send_all(r);
            st.add(ws.sweep_part(r, in.data(), (int64_t)in.size()));
        } else {
            st = ws.sweep_part(r, in.data(), (int64_t)in.size());
            check(MPI_Waitall((int)requests_.size(), requests_.data(), MPI_STATUSES_IGNORE), "MPI_Waitall");
            requests_.clear();
            st.add(ws.sweep_part(r, b.data(), (int64_t)b.size()));
            send_all(r);
        }
        receive(higher_, r);
        check(MPI_Waitall((int)requests_.size(), requests_.data(), MPI_STATUSES_IGNORE), "MPI_Waitall");
        // The sweep's statistics over the ranks, in rank order.
        const double mine[5] = {st.dr2, st.r2, (double)st.rejected, (double)st.unsolved, (double)st.frozen};
        const std::vector<double> all = gather_all(comm_, mine, 5);
        nsgs::SweepStats total;
        total.dr2 = all[0], total.r2 = all[1];
        for (size_t k = 1; 5 * k < all.size(); ++k) total.dr2 += all[5 * k], total.r2 += all[5 * k + 1];
        for (size_t k = 0; 5 * k < all.size(); ++k) {
            total.rejected += (int64_t)all[5 * k + 2];
            total.unsolved += (int64_t)all[5 * k + 3];
            total.frozen += (int64_t)all[5 * k + 4];
        }
        return total;
    }

    Measures exact(const double *r, double *u) override {
        const int64_t nc = p_.owned;
        if (nc > 0) {
            matrix_gemv(p_.W, 1.0, r, 0.0, u);
            for (int64_t i = 0; i < 3 * nc; ++i) u[i] += p_.q[(size_t)i];
        }
        const MeasureParts mine = measure_parts(r, u, p_.mu.data(), 0, nc);
        const double packed[6] = {mine.residual_sq, mine.cone, mine.penetration, mine.complementarity, mine.r_sq, mine.u_sq};
        const std::vector<double> all = gather_all(comm_, packed, 6);
        MeasureParts total;
        for (size_t k = 0; 6 * k < all.size(); ++k) {
            MeasureParts part;
            part.residual_sq = all[6 * k], part.cone = all[6 * k + 1], part.penetration = all[6 * k + 2];
            part.complementarity = all[6 * k + 3], part.r_sq = all[6 * k + 4], part.u_sq = all[6 * k + 5];
            if (k == 0)
                total = part;
            else
                total.add(part);
        }
        RanksRescue rescue(comm_, r, u, p_.mu.data(), nc);
        return measures_from_parts(total, rescue, norm_q_);
    }

    unsigned agree(unsigned flags) override { return or_all(comm_, flags); }
    int64_t all_contacts(int64_t) const override { return p_.total; }

    // Every ghost from its owner: at the start, and after r changed outside a sweep.
    void exchange(double *r) {
        requests_.clear();
        std::vector<size_t> all(p_.neighbours.size());
        for (size_t k = 0; k < all.size(); ++k) all[k] = k;
        receive(all, r);
        send_all(r);
        check(MPI_Waitall((int)requests_.size(), requests_.data(), MPI_STATUSES_IGNORE), "MPI_Waitall");
        requests_.clear();
    }

   private:
    // Receives the ghosts of the neighbours listed (indices into p.neighbours) into r.
    void receive(const std::vector<size_t> &which, double *r) {
        for (const size_t k : which) {
            const int64_t from = p_.recv_ptr[k], to = p_.recv_ptr[k + 1];
            if (to == from) continue;
            requests_.emplace_back();
            check(MPI_Irecv(r + 3 * (p_.owned + from), (int)(3 * (to - from)), MPI_DOUBLE, p_.neighbours[k], kTag,
                            comm_, &requests_.back()),
                  "MPI_Irecv");
        }
    }
    // Sends each neighbour the owned reactions it needs.
    void send_all(const double *r) {
        for (size_t k = 0; k < p_.neighbours.size(); ++k) {
            const int64_t from = p_.send_ptr[k], to = p_.send_ptr[k + 1];
            if (to == from) continue;
            double *buffer = send_buffer_.data() + 3 * from;
            for (int64_t e = from; e < to; ++e)
                for (int i = 0; i < 3; ++i) buffer[3 * (e - from) + i] = r[3 * p_.send[(size_t)e] + i];
            requests_.emplace_back();
            check(MPI_Isend(buffer, (int)(3 * (to - from)), MPI_DOUBLE, p_.neighbours[k], kTag, comm_,
                            &requests_.back()),
                  "MPI_Isend");
        }
    }

    const frix_mpi_problem &p_;
    MPI_Comm comm_;
    double norm_q_;
    std::vector<double> send_buffer_;
    std::vector<MPI_Request> requests_;
    std::vector<size_t> lower_, higher_;  // neighbours of lower and higher colours
};

bool finite_measures(const Measures &m) { return std::isfinite(m.relative) && std::isfinite(m.norm_u); }

// The driver (as solve_local_problem for one process): the all-separating case, the warm
// start, the sweeps, the final measures and the status check against them.
frix_error solve(frix_mpi_problem &p, const frix_options &opts, double *r_out, double *u_out, frix_info &info,
                 const Stopwatch &clock) {
    const MPI_Comm comm = p.ctx->comm;
    const int64_t m = 3 * p.owned;
    std::vector<double> r((size_t)(3 * (p.owned + (int64_t)p.ghosts.size())), 0.0);
    std::copy(r_out, r_out + m, r.begin());
    for (int64_t i = 0; i < m; ++i)
        if (!std::isfinite(r[(size_t)i])) r[(size_t)i] = 0.0;
    bool approaching = false;
    for (int64_t a = 0; a < p.owned && !approaching; ++a) approaching = p.q[3 * (size_t)a] < 0.0;
    const bool separating = or_all(comm, approaching ? 1u : 0u) == 0;
    const bool cold = or_all(comm, std::any_of(r.begin(), r.begin() + m, [](double x) { return x != 0.0; }) ? 1u : 0u) == 0;
    const std::vector<double> warm_start = cold ? std::vector<double>() : std::vector<double>(r.begin(), r.begin() + m);
    DistributedRows form(p);
    bool ran = false;
    if (p.total == 0 || separating) {
        std::fill(r.begin(), r.end(), 0.0);
        info.status = FRIX_STATUS_CONVERGED;
        info.iterations = 0;
    } else {
        ran = true;
        form.exchange(r.data());
        nsgs::Workspace ws(p.view, nsgs::settings_from(opts));
        SolveContext ctx{p.view, opts, r.data(), u_out, nullptr, info, clock, nullptr, nullptr, nullptr};
        if (frix_error e = nsgs::run_sweeps(ctx, ws, form, "nsgs")) return e;
    }
    Measures meas = form.exact(r.data(), u_out);
    if (!finite_measures(meas) && ran) {
        std::fill(r.begin(), r.end(), 0.0);
        if (!warm_start.empty()) std::copy(warm_start.begin(), warm_start.end(), r.begin());
        form.exchange(r.data());
        meas = form.exact(r.data(), u_out);
        if (!finite_measures(meas)) {
            std::fill(r.begin(), r.end(), 0.0);
            meas = form.exact(r.data(), u_out);
        }
        info.status = FRIX_STATUS_DIVERGED;
    }
    std::copy(r.begin(), r.begin() + m, r_out);
    record_measures(info, meas, opts.i(FRIX_OPT_ERROR_MEASURE));
    if (info.status == FRIX_STATUS_CONVERGED && !(info.error <= info.tolerance)) info.status = FRIX_STATUS_STAGNATED;
    return FRIX_OK;
}

// The options a distributed solve runs with: nsgs's, checked alike on every rank; only rank 0
// logs.
frix_error check_options(const frix_options *given, int rank, frix_options &out) {
    const char *where = "frix_mpi_solve";
    if (!given) {
        frix_options *o = nullptr;
        if (frix_error e = frix_options_create(FRIX_SOLVER_NSGS, &o)) return e;
        out = *o;
        frix_options_free(o);
    } else {
        if (given->solver_id != FRIX_SOLVER_NSGS)
            return fail(FRIX_ERR_UNSUPPORTED, "%s: solver %d is not distributed (only nsgs, %d)", where,
                        given->solver_id, (int)FRIX_SOLVER_NSGS);
        out = *given;
    }
    if (out.i(FRIX_OPT_DRIFT_WINDOW) != 0 || out.i(FRIX_OPT_ACCELERATION) != 0 ||
        out.i(FRIX_OPT_SHUFFLE) != FRIX_SHUFFLE_NONE)
        return fail(FRIX_ERR_UNSUPPORTED, "%s: drift_window, acceleration and shuffle are not distributed (set them to 0)",
                    where);
    if (rank != 0) out.ivalue[FRIX_OPT_VERBOSITY] = 0;
    return FRIX_OK;
}

}  // namespace
}  // namespace mpi
}  // namespace frix

extern "C" {

FRIX_API frix_error frix_mpi_solve(frix_mpi_problem *p, const frix_options *options, double *r, double *u,
                                   frix_info *info) {
    frix::Stopwatch clock;
    return frix::guard("frix_mpi_solve", [&]() -> frix_error {
        using frix::fail;
        if (!p) return fail(FRIX_ERR_INVALID_ARGUMENT, "frix_mpi_solve: p is NULL");
        const MPI_Comm comm = p->ctx->comm;
        frix_options opts;
        frix_error e = frix::mpi::check_options(options, p->ctx->rank, opts);
        if (!e && p->owned > 0 && (!r || !u))
            e = fail(FRIX_ERR_INVALID_ARGUMENT, "frix_mpi_solve: r and u are required (%lld entries each)",
                     (long long)(3 * p->owned));
        if (frix_error agreed = frix::mpi::agree(comm, e, "frix_mpi_solve")) return agreed;
        frix_info local_info;
        frix_info &out = info ? *info : local_info;
        out = frix_info();
        out.solver_id = FRIX_SOLVER_NSGS;
        out.contacts = p->total;
        out.tolerance = opts.d(FRIX_OPT_TOLERANCE);
        e = frix::mpi::solve(*p, opts, r, u, out, clock);
        out.solve_time = clock.seconds();
        return e;
    });
}

}  // extern "C"
