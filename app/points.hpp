// app/points.hpp — the `kappa,cosine` points file shared by `sglab reference`
// and `sglab eval` (one reader, one validation; defined in cmd_reference.cpp).
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>

#include "common/args.hpp"
#include "reference/reference.hpp"

namespace sglab::app {

// The longest line of a points file (a `κ,c` row needs fewer than 60 bytes).
inline constexpr std::size_t kMaxPointsLineBytes = 1024;

// Reads a CSV file with the header `kappa,cosine` and one `κ,c` per line
// (finite κ ≥ 0, c ∈ [−1, 1]; CRLF and blanks around fields accepted, empty
// lines skipped) once, calling on_point for each row as soon as it is read
// and checked; returns the number of rows. Nothing is held but the current
// line (at most kMaxPointsLineBytes), so memory does not grow with the file.
// A bad line is an InputError naming the file and the line number and
// quoting the line escaped and shortened (io::quote_escaped), thrown
// after on_point saw every row before it. With `kappa_format` (the precision
// the rows are evaluated in, e.g. float for `eval --precision float`), a κ
// that does not survive rounding to it is refused as the κ-range parser
// refuses one (common/args.hpp): above its largest finite value, or nonzero
// and rounding to 0.
std::size_t for_each_point(const std::string& path,
                           const std::function<void(const reference::Query&)>& on_point,
                           std::optional<io::NumberFormat> kappa_format = std::nullopt);

}  // namespace sglab::app
