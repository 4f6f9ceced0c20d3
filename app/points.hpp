// app/points.hpp — the `kappa,cosine` points file shared by `sglab reference`
// and `sglab eval` (one reader, one validation; defined in cmd_reference.cpp).
#pragma once

#include <string>
#include <vector>

#include "reference.hpp"

namespace sglab::app {

// Reads a CSV file with the header `kappa,cosine` and one `κ,c` per line
// (finite κ ≥ 0, c ∈ [−1, 1]; CRLF and blanks around fields accepted, empty
// lines skipped). Any bad line is an InputError naming the file and line.
std::vector<validate::Query> read_points(const std::string& path);

}  // namespace sglab::app
