// Cost of one NSGS sweep against one sparse-block product W r on the same problem.
//
//   nsgs_sweep [--out FILE.csv] [--reps N] [--warmup SWEEPS] FILE.hdf5...
//
// A sweep reads every block of W once, like the product, and adds one local solve per
// contact: the goal is sweep <= 2x product. r is first brought to a realistic state by
// `warmup` sweeps from 0 (a mix of take-off, stick and slide). Each figure is the median over
// `reps` timings, each timing repeating the operation until it lasts >= 2 ms.
#include <frix/frix.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include "src/matrix.hpp"
#include "solvers/kit/sweeps.hpp"
#include "src/problem.hpp"

namespace {

double seconds_per_call(const std::function<void()> &op, int reps) {
    using clock = std::chrono::steady_clock;
    std::vector<double> t;
    int64_t inner = 1;
    for (int k = 0; k < reps;) {
        const auto start = clock::now();
        for (int64_t i = 0; i < inner; ++i) op();
        const double s = std::chrono::duration<double>(clock::now() - start).count();
        if (s < 2e-3 && inner < (int64_t(1) << 40)) {
            inner *= 2;  // too short to time reliably: lengthen and start again
            t.clear();
            k = 0;
            continue;
        }
        t.push_back(s / (double)inner);
        ++k;
    }
    std::nth_element(t.begin(), t.begin() + (long)t.size() / 2, t.end());
    return t[t.size() / 2];
}

const char *base_name(const char *path) {
    const char *slash = std::strrchr(path, '/');
    return slash ? slash + 1 : path;
}

}  // namespace

int main(int argc, char **argv) {
    const char *out_path = nullptr;
    int reps = 7, warmup = 50;
    std::vector<const char *> files;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--out") && i + 1 < argc) out_path = argv[++i];
        else if (!std::strcmp(argv[i], "--reps") && i + 1 < argc) reps = std::max(1, std::atoi(argv[++i]));
        else if (!std::strcmp(argv[i], "--warmup") && i + 1 < argc) warmup = std::max(0, std::atoi(argv[++i]));
        else if (argv[i][0] == '-') {
            std::fprintf(stderr, "usage: %s [--out FILE.csv] [--reps N] [--warmup SWEEPS] FILE.hdf5...\n", argv[0]);
            return 2;
        } else files.push_back(argv[i]);
    }
    FILE *out = out_path ? std::fopen(out_path, "w") : stdout;
    if (!out) {
        std::perror(out_path);
        return 1;
    }
    std::fprintf(out, "file,nc,nnz,blocks,product_s,sweep_s,ratio\n");
    int status = 0;
    for (const char *path : files) {
        frix_problem *p = nullptr;
        if (frix_fclib_read(path, &p) != FRIX_OK) {
            std::fprintf(stderr, "%s: %s\n", path, frix_last_error_message());
            status = 1;
            continue;
        }
        if (p->kind != FRIX_PROBLEM_LOCAL || p->nc == 0) {
            std::fprintf(stderr, "%s: not a local problem with contacts, skipped\n", path);
            frix_problem_free(p);
            continue;
        }
        frix_options *o = nullptr;
        frix_options_create(FRIX_SOLVER_NSGS, &o);
        frix::nsgs::Workspace ws(*p, frix::nsgs::settings_from(*o));
        std::vector<double> r((size_t)(3 * p->nc), 0.0), y(r.size());
        for (int k = 0; k < warmup; ++k) ws.sweep(r.data());

        const frix_matrix &W = *p->W;
        const double product = seconds_per_call([&] { frix::matrix_gemv(W, 1.0, r.data(), 0.0, y.data()); }, reps);
        const double sweep = seconds_per_call([&] { ws.sweep(r.data()); }, reps);
        std::fprintf(out, "%s,%lld,%lld,%lld,%.4e,%.4e,%.3f\n", base_name(path), (long long)p->nc,
                     (long long)frix_matrix_nnz(&W), (long long)frix_matrix_block_count(&W), product,
                     sweep, sweep / product);
        std::fflush(out);
        frix_options_free(o);
        frix_problem_free(p);
    }
    if (out != stdout) std::fclose(out);
    return status;
}
