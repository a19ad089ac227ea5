// The price of forming W = H^T M^-1 H against the time it takes (notes/2026-11-28-w-price.md).
//
//   w_price [--runs N] FILE.hdf5...
//
// For each global problem: M factorised (MassSolver, as the driver does), W's price
// (MassSolver::congruence_price: flops and writes), W formed N times (default 1) and the
// fastest timed, as the rates are the fastest of their runs, and the price in
// seconds at this process's measured rates (Stopwatch::factor_rate and write_rate, those a
// time limit uses): predicted / measured. One CSV line per file.
#include <frix/frix.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>

#include "src/reduction.hpp"
#include "src/solver_api.hpp"

int main(int argc, char **argv) {
    int first = 1, runs = 1;
    if (argc > 2 && !std::strcmp(argv[1], "--runs")) {
        runs = std::max(1, std::atoi(argv[2]));
        first = 3;
    }
    if (argc <= first) {
        std::fprintf(stderr, "usage: %s [--runs N] FILE.hdf5...\n", argv[0]);
        return 2;
    }
    const frix::Stopwatch clock;
    const double flop_rate = clock.factor_rate(), write_rate = clock.write_rate();
    std::printf("# flop rate %.3g /s, write rate %.3g /s\n", flop_rate, write_rate);
    std::printf("file,contacts,m_seconds,w_flops,w_writes,w_predicted,w_seconds,predicted_over_measured\n");
    int status = 0;
    for (int i = first; i < argc; ++i) {
        frix_problem *p = nullptr;
        if (frix_read_problem(argv[i], &p) != FRIX_OK || !p->M) {
            std::fprintf(stderr, "%s: %s\n", argv[i], p ? "not a global problem" : frix_last_error_message());
            frix_problem_free(p);
            status = 1;
            continue;
        }
        frix::MassSolver ms;
        frix::linalg::FactorPrice price;
        const frix::Stopwatch factor;
        bool ok = ms.factor(*p->M) == FRIX_OK;
        const double m_seconds = factor.seconds();
        if (ok && !ms.congruence_price(*p->H, &price)) {
            std::printf("%s,%lld,%.4g,not priced (M has no Cholesky factor),,,,\n", argv[i], (long long)p->nc,
                        m_seconds);
            frix_problem_free(p);
            continue;
        }
        double w_seconds = INFINITY;
        for (int run = 0; run < runs && ok; ++run) {
            std::unique_ptr<frix_matrix> W;
            bool stopped = false;
            const frix::Stopwatch forming;
            ok = ms.congruence(*p->H, 0.0, W, nullptr, stopped) == FRIX_OK;
            w_seconds = std::min(w_seconds, forming.seconds());
        }
        if (!ok) {
            std::fprintf(stderr, "%s: W not priced or formed (%s)\n", argv[i], frix_last_error_message());
            status = 1;
        } else {
            const double predicted = price.flops / flop_rate + price.writes / write_rate;
            std::printf("%s,%lld,%.4g,%.4g,%.4g,%.4g,%.4g,%.3g\n", argv[i], (long long)p->nc, m_seconds, price.flops,
                        price.writes, predicted, w_seconds, predicted / w_seconds);
            std::fflush(stdout);
        }
        frix_problem_free(p);
    }
    return status;
}
