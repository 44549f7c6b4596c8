#pragma once
// How a distributed run shares the model's elements and reduced unknowns among its processes
// (linalg/distribution.hpp), and the figures that describe the sharing (summary.json "partition").
//
// graph: the fixed elements (bodies, loads, inertia) are the vertices of their adjacency graph (two
// elements are adjacent when they share a reduced unknown; the edge's weight: how many they share),
// weighted by their cost, the square of their DOF count (the entries of their element matrix), and
// partitioned by Distribution::partition (PT-Scotch);
// an element is evaluated by the process of its part. An unknown is owned by the process with the most of
// the elements that touch it (ties: the lowest rank; an unknown no element touches: process 0).
// contiguous: the unknowns in contiguous ranges, an element evaluated by the owner of its smallest unknown.
// In both, the variable elements (interactions, rebuilt as their pairs change) are evaluated by the owner
// of their smallest unknown, and an element that touches no unknown by its part (graph) or process 0.
#include <string>
#include <vector>

#include "linalg/constraints.hpp"
#include "linalg/distribution.hpp"

namespace fibrane::solve {

// The sharing of the fixed elements and the unknowns, and what it costs.
struct ElementPartition {
  Partitioning method = Partitioning::contiguous;
  std::string note;                // why the graph partition was not used, when it was asked for
  std::vector<int> element_owner;  // per fixed element: the process that evaluates it
  UnknownOwnership unknowns;
  // Per process: its fixed elements, and their weight.
  std::vector<int> elements;
  std::vector<double> weight;
  int interface_unknowns = 0;  // unknowns touched by the fixed elements of more than one process
  double imbalance = 1.0;      // largest weight of a process / the mean
};

// The reduced unknowns each element's DOFs expand into, sorted, without repeats.
std::vector<std::vector<int>> element_unknowns(const ConstraintSet& constraints,
                                               const std::vector<std::vector<int>>& element_dofs);

// The adjacency graph of the elements (`unknowns`: element_unknowns; n: the number of unknowns); edge
// weights: the unknowns two elements share; vertex weights: the square of each element's DOF count
// (`dofs`: the elements' DOF lists), at least 1, scaled down so that their sum stays below 2^30.
Graph element_graph(const std::vector<std::vector<int>>& unknowns, const std::vector<std::vector<int>>& dofs, int n);

// Collective. The sharing by distribution.partitioning(); a graph partition that the distribution cannot
// make falls back to contiguous ranges, with `note` saying why.
ElementPartition partition_elements(const std::vector<std::vector<int>>& unknowns,
                                    const std::vector<std::vector<int>>& dofs, int n, const Distribution& distribution);

// The owner of the smallest of an element's `unknowns` (sorted); process 0 when it has none.
int smallest_unknown_owner(const std::vector<int>& unknowns, const UnknownOwnership& ownership);

// The owners of the unknowns under the rule above, given the process of every element.
UnknownOwnership owners_by_elements(const std::vector<std::vector<int>>& unknowns, const std::vector<int>& element_owner,
                                    int n, int processes);

}  // namespace fibrane::solve
