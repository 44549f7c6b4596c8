#include "linalg/dof_map.hpp"

#include <stdexcept>

#include "common/error.hpp"

namespace fibrane::solve {

int DofMap::add_block(std::string name, int num_nodes, int dofs_per_node) {
  if (num_nodes < 0 || dofs_per_node <= 0)
    throw InputError("DOF block '" + name + "': need num_nodes >= 0 and dofs_per_node > 0, got " +
                     std::to_string(num_nodes) + " and " + std::to_string(dofs_per_node));
  blocks_.push_back({std::move(name), total_, num_nodes, dofs_per_node});
  total_ += num_nodes * dofs_per_node;
  return num_blocks() - 1;
}

const DofMap::Block& DofMap::at(int b) const {
  if (b < 0 || b >= num_blocks())
    throw std::out_of_range("DofMap: block " + std::to_string(b) + " does not exist");
  return blocks_[static_cast<size_t>(b)];
}

int DofMap::dof(int block, int node, int component) const {
  const Block& bl = at(block);
  if (node < 0 || node >= bl.num_nodes || component < 0 || component >= bl.dofs_per_node)
    throw std::out_of_range("DofMap: node " + std::to_string(node) + " component " +
                            std::to_string(component) + " out of range in block '" + bl.name + "'");
  return bl.offset + node * bl.dofs_per_node + component;
}

int DofMap::find_block(const std::string& name) const {
  for (int b = 0; b < num_blocks(); ++b)
    if (blocks_[static_cast<size_t>(b)].name == name) return b;
  return -1;
}

}  // namespace fibrane::solve
