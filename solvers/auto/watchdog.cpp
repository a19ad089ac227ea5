// The shared state of auto's stages and their watchdog (watchdog.hpp).
#include "solvers/auto/watchdog.hpp"

#include <algorithm>
#include <cstdio>

#include "src/log.hpp"

namespace frix::autosolve {

frix_status Shared::ending(bool converged, bool stopped) const {
    if (converged) return FRIX_STATUS_CONVERGED;
    if (stopped) return FRIX_STATUS_STOPPED_BY_CALLBACK;
    // The callback has had its say (stop_requested): the limits are asked without it, so that
    // it is not called once more.
    frix_options asked = user;
    asked.callback = nullptr;
    asked.callback_with_kind = nullptr;
    return Monitor(asked, clock).limits(iterations.load(), NAN);
}

void Shared::log(void *data, const char *line) {
    Shared *shared = static_cast<Shared *>(data);
    std::lock_guard<std::mutex> guard(shared->log_lock);
    log_line(&shared->user, "%s", line);
}

int Watchdog::on_progress(int64_t iteration, double error, bool measured) {
    shared->iterations += iteration - last_iteration;
    last_iteration = iteration;
    if (shared->stop_requested) return 1;  // asked by the caller, seen in another part
    if (shared->user.has_callback()) {
        std::lock_guard<std::mutex> guard(shared->lock);
        const Monitor caller(shared->user, shared->clock);
        const int64_t done = shared->iterations.load();
        if (measured && whole_problem ? caller.report(done, error) : caller.report_estimate(done, error))
            shared->stop_requested = true;
    }
    if (shared->stop_requested) return 1;
    // The caller's max_iter bounds the sum of the stages' own units, PROX's inner Newton
    // steps among them, which PROX's own limit (on its outer steps) does not bound.
    if (shared->out_of_iterations()) return stop("iteration limit");
    if (kind == Watch::Newton) return judge_newton(error, measured);
    if (std::isfinite(error) && error < best) best = error;
    if (best <= 0.1 * ref || (!std::isfinite(ref) && std::isfinite(best))) {
        ref = best;
        ref_iteration = iteration;
    }
    if (kind == Watch::Rate) return judge_rate(judged_error(error), iteration);
    const int64_t idle = iteration - ref_iteration;
    if (idle >= patience && 2 * idle >= iteration) return stop("no tenfold progress");
    return 0;
}

// A step is slow where its error (not finite: slow) does not bring the best below
// kNewtonSlowStepRatio times the best before; the errors judged are the measured ones, from
// newton_start on, once the stage reports any, else its estimates.
int Watchdog::judge_newton(double error, bool measured) {
    if (measured && !measured_seen) measured_seen = true, best = newton_start;
    if (measured_seen && !measured) return 0;
    const bool gained = std::isfinite(error) && error <= kNewtonSlowStepRatio * best;
    if (std::isfinite(error) && error < best) best = error;
    slow_steps = gained ? 0 : slow_steps + 1;
    return slow_steps >= patience ? stop(creeping) : 0;
}

// The iterations the rate may predict to the tolerance before the stage is stopped.
double Watchdog::limit(int64_t sweeps, double allowed) const {
    if (!patient) return allowed;
    const double multiple = iteration_work > 0.0 ? kPricedPatience : kNsgsPatience;
    return std::max(multiple * (double)sweeps, allowed);
}

bool Watchdog::rate_gain(double error, int64_t sweeps, double *gained, int64_t *from) {
    if (iteration_work > 0.0) {
        if (sweeps >= next_sample) {
            samples.emplace_back(sweeps, error);
            while (next_sample <= sweeps) next_sample *= 2;
        }
        if (sweeps < min_sweeps) return false;
        const std::pair<int64_t, double> *mid = nullptr;
        for (const auto &x : samples)
            if (2 * x.first <= sweeps) mid = &x;
        if (!mid) return false;
        *from = mid->first;
        *gained = std::log(mid->second / error);
        return true;
    }
    // Keep a sample near half the sweeps so far: the rate over the second half.
    if (std::isnan(mid_error) || 4 * mid_sweep < sweeps) {
        mid_error = std::isnan(last_error) ? error : last_error;
        mid_sweep = std::isnan(last_error) ? sweeps : last_sweep;
    }
    last_error = error, last_sweep = sweeps;
    if (sweeps < min_sweeps || sweeps <= mid_sweep) return false;
    *from = mid_sweep;
    *gained = std::log(mid_error / error);
    return true;
}

int Watchdog::judge_rate(double error, int64_t sweeps) {
    if (!std::isfinite(error)) return stop("non-finite error");
    double gained = 0.0;  // > 0 when converging
    int64_t from = 0;     // over the sweeps from `from` on
    if (!rate_gain(error, sweeps, &gained, &from)) return 0;
    const double needed = std::log(error / tolerance);
    if (needed <= 0.0) return 0;
    predicted = gained > 0.0 ? needed / gained * (double)(sweeps - from) : INFINITY;
    const double allowed = iteration_work > 0.0 ? alternative_work / iteration_work : 0.0;
    if (shared->user.i(FRIX_OPT_VERBOSITY) >= 3 && !samples.empty() && samples.back().first == sweeps)
        log_rate(sweeps, error, allowed);
    if (predicted > limit(sweeps, allowed)) return stop(slow);
    return 0;
}

void Watchdog::log_rate(int64_t sweeps, double error, double allowed) const {
    char line[200];
    std::snprintf(line, sizeof line, "auto: rate watch at %lld: error %.3e, predicts %.4g more, allowed %.4g",
                  (long long)sweeps, error, predicted, limit(sweeps, allowed));
    Shared::log(shared, line);
}

int64_t nsgs_min_sweeps(int64_t blocks) {
    return std::max<int64_t>(kNsgsMinSweeps, (int64_t)(kNsgsMinWork / (double)std::max<int64_t>(1, blocks)));
}

}  // namespace frix::autosolve
