#pragma once
// The bench programs' common options: `--threads N` and `--replace FROM TO` (a copy of a case file with
// text replaced, to change the mesh of an example without editing it).
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "common/error.hpp"
#include "linalg/linear_solver.hpp"

// Runs a bench program's body. An input error (a case file, a checkpoint given with --state) is printed with
// exit code 2, any other exception with exit code 1, as `fibrane` does, instead of ending in std::terminate.
inline int guarded_main(int argc, char** argv, int (*body)(int, char**)) {
  try {
    return body(argc, argv);
  } catch (const fibrane::InputError& e) {
    std::cerr << argv[0] << ": error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << argv[0] << ": " << e.what() << "\n";
    return 1;
  }
}

// True (after printing `usage` on stdout) when the first argument asks for help: the caller returns 0.
inline bool help_requested(int argc, char** argv, const char* usage) {
  if (argc < 2) return false;
  const std::string a = argv[1];
  if (a != "--help" && a != "-h") return false;
  std::fputs(usage, stdout);
  return true;
}

// The path of the edited copy (in the temporary directory), or `path` itself without edits. Throws
// std::runtime_error if a FROM is not in the file.
inline std::string edited_case(const std::string& path, const std::vector<std::pair<std::string, std::string>>& edits) {
  if (edits.empty()) return path;
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  std::string text = ss.str();
  for (const auto& [from, to] : edits) {
    const auto at = text.find(from);
    if (at == std::string::npos) throw std::runtime_error("--replace: '" + from + "' not found in " + path);
    text.replace(at, from.size(), to);
  }
  const auto edited = std::filesystem::temp_directory_path() /
                      (std::filesystem::path(path).stem().string() + "-edited.yaml");
  std::ofstream(edited) << text;
  return edited.string();
}

// Consumes argv[i] (and its values) if it is --threads or --replace; returns false for other arguments.
inline bool common_option(int argc, char** argv, int& i, std::vector<std::pair<std::string, std::string>>& edits) {
  const std::string a = argv[i];
  if (a == "--threads" && i + 1 < argc) {
    fibrane::solve::set_thread_count(std::stoi(argv[++i]));  // OpenMP and OpenBLAS
    return true;
  }
  if (a == "--replace" && i + 2 < argc) {
    edits.emplace_back(argv[i + 1], argv[i + 2]);
    i += 2;
    return true;
  }
  return false;
}

// `PROGRAM CASE.yaml [options]`: the program's own options go to `own(argument, i)`, which consumes
// argv[i] (and its values, advancing i) and returns true when the argument is one of them; --threads and
// --replace are common_option's. Returns the (edited) case's path, or std::nullopt with `code` the exit
// code: 0 after --help, 2 after the usage or an error on stderr (no case, an unknown argument, a
// --replace whose FROM is not in the case).
inline std::optional<std::string> case_arguments(int argc, char** argv, const char* usage,
                                                 const std::function<bool(const std::string&, int&)>& own,
                                                 int& code) {
  code = 2;
  if (help_requested(argc, argv, usage)) {
    code = 0;
    return std::nullopt;
  }
  if (argc < 2) {
    std::cerr << usage;
    return std::nullopt;
  }
  std::vector<std::pair<std::string, std::string>> edits;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (!own(a, i) && !common_option(argc, argv, i, edits)) {
      std::cerr << "unknown argument " << a << "\n";
      return std::nullopt;
    }
  }
  try {
    return edited_case(argv[1], edits);
  } catch (const std::exception& e) {
    std::cerr << e.what() << "\n";
    return std::nullopt;
  }
}
