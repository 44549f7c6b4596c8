#pragma once
// Forward declarations for headers that only pass the solver's objects by reference.
namespace fibrane::solve {
class DofMap;
class Distribution;
struct RankOneTerms;
class SparseAssembler;
}  // namespace fibrane::solve
