#include "common/vocabulary.hpp"

namespace sglab::io {

std::string to_string(const Evaluation& e) {
  if (e.backend == Backend::cpu) return std::string(to_string(e.precision));
  std::string out = "vulkan";
  if (e.language == Language::hlsl) out += "_hlsl";
  if (e.precision == Precision::float16) out += "_half";
  if (e.form == Form::split) out += "_split";
  return out;
}

}  // namespace sglab::io
