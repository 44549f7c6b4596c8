#pragma once
// Global numbering of the degrees of freedom of several bodies ("blocks"): a shell's control points,
// a beam's nodes, ... Each block owns a contiguous range; inside it the numbering is node-major,
//   dof = offset + node * dofs_per_node + component,
// so the DOFs of one node are adjacent (good locality for element scatter).
#include <string>
#include <vector>

namespace fibrane::solve {

class DofMap {
 public:
  // Appends a block after the existing ones; returns its id. Throws InputError on negative sizes.
  int add_block(std::string name, int num_nodes, int dofs_per_node);

  // Global DOF of (block, node, component); throws std::out_of_range on a bad index.
  int dof(int block, int node, int component) const;

  int size() const { return total_; }
  int num_blocks() const { return static_cast<int>(blocks_.size()); }
  int block_offset(int b) const { return at(b).offset; }
  int block_size(int b) const { return at(b).num_nodes * at(b).dofs_per_node; }
  int num_nodes(int b) const { return at(b).num_nodes; }
  int dofs_per_node(int b) const { return at(b).dofs_per_node; }
  const std::string& block_name(int b) const { return at(b).name; }
  // Block id by name, -1 if absent.
  int find_block(const std::string& name) const;

 private:
  struct Block {
    std::string name;
    int offset = 0, num_nodes = 0, dofs_per_node = 0;
  };
  const Block& at(int b) const;
  std::vector<Block> blocks_;
  int total_ = 0;
};

}  // namespace fibrane::solve
