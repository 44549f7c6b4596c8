// The BLAS that the sparse factorisations run on, alone: which OpenBLAS kernel it chose for this processor,
// and the speed of a dense dgemm and of LAPACK's dpotrf at each thread count given, so that a machine's
// factorisation times can be read against its dense speed (docs/performance.md, "Threads on a 16-core
// machine").
//   bench_dense_blas [--size N = 4000] [THREADS...]   (default: 1, 2 and the cores)
//   bench_dense_blas --upgrade    prints the OPENBLAS_CORETYPE that fibrane would set (blas_core_upgrade), or
//                                 nothing where OpenBLAS's own choice fits the processor
#include <dlfcn.h>
#include <omp.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "linalg/linear_solver.hpp"

extern "C" {
void dgemm_(const char* transa, const char* transb, const int* m, const int* n, const int* k, const double* alpha,
            const double* a, const int* lda, const double* b, const int* ldb, const double* beta, double* c,
            const int* ldc);
void dpotrf_(const char* uplo, const int* n, double* a, const int* lda, int* info);
}

namespace {

// OpenBLAS's own account of itself, where the loaded BLAS is OpenBLAS.
std::string openblas_text(const char* symbol) {
  using Text = char* (*)();
  auto* f = reinterpret_cast<Text>(dlsym(RTLD_DEFAULT, symbol));
  return f ? f() : "(not OpenBLAS)";
}

template <class F>
double best_seconds(F&& f, int repetitions) {
  double best = 1e30;
  for (int r = 0; r < repetitions; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  int n = 4000;
  std::vector<int> threads;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--upgrade") {
      std::printf("%s\n", fibrane::solve::blas_core_upgrade().c_str());
      return 0;
    }
    if (a == "--size" && i + 1 < argc) n = std::atoi(argv[++i]);
    else threads.push_back(std::atoi(argv[i]));
  }
  if (threads.empty()) threads = {1, 2, omp_get_num_procs()};
  std::printf("OpenBLAS core: %s; config: %s; OPENBLAS_CORETYPE=%s; fibrane's upgrade: %s\n",
              openblas_text("openblas_get_corename").c_str(), openblas_text("openblas_get_config").c_str(),
              std::getenv("OPENBLAS_CORETYPE") ? std::getenv("OPENBLAS_CORETYPE") : "(unset)",
              fibrane::solve::blas_core_upgrade().empty() ? "none" : fibrane::solve::blas_core_upgrade().c_str());
  const Eigen::MatrixXd a = Eigen::MatrixXd::Random(n, n), b = Eigen::MatrixXd::Random(n, n);
  Eigen::MatrixXd spd = a * a.transpose();
  spd.diagonal().array() += n;
  std::printf("| threads | dgemm %d GFlop/s | dpotrf %d GFlop/s |\n|---|---|---|\n", n, n);
  for (const int t : threads) {
    fibrane::solve::set_thread_count(t);
    Eigen::MatrixXd c(n, n);
    const double one = 1, zero = 0;
    const double gemm = best_seconds([&] { dgemm_("N", "N", &n, &n, &n, &one, a.data(), &n, b.data(), &n, &zero, c.data(), &n); }, 3);
    const double potrf = best_seconds(
        [&] {
          c = spd;
          int info = 0;
          dpotrf_("L", &n, c.data(), &n, &info);
        },
        3);
    const double nd = n;
    std::printf("| %d | %.1f | %.1f |\n", t, 2 * nd * nd * nd / gemm / 1e9, nd * nd * nd / 3 / potrf / 1e9);
  }
  return 0;
}
