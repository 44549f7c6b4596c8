#pragma once
// A sum over the threads of a parallel region that is the same in every run with the same number of
// threads: each thread stores its part, and total() adds the parts in thread order. (An OpenMP
// `reduction(+ : x)` adds the threads' parts in the order the threads finish, so its last bits vary from
// run to run.) With a static schedule, which elements a thread adds is fixed as well.
#include <omp.h>

#include <cstddef>
#include <vector>

namespace fibrane::model {

// Usage: OrderedSum sum; #pragma omp parallel { double part = 0; ...; sum.set(part); } return sum.total();
class OrderedSum {
 public:
  OrderedSum() : parts_(static_cast<std::size_t>(omp_get_max_threads()), 0.0) {}
  // Called once by each thread of the region, with its part.
  void set(double part) { parts_[static_cast<std::size_t>(omp_get_thread_num())] = part; }
  double total() const {
    double sum = 0.0;
    for (double p : parts_) sum += p;
    return sum;
  }

 private:
  std::vector<double> parts_;
};

}  // namespace fibrane::model
