// python/module.cpp — the extension module sglab._sglab (pybind11): the
// runtime's methods, their exact gradients, the reference engine, the shader
// export and the environment maps, on NumPy arrays. The package sglab
// (python/sglab/) prepares the arrays (dtype, broadcasting, layout) and calls
// these functions, which take C-contiguous float32 or float64 arrays of one
// shape, check every point by the rules of `sglab eval` (io::point_error),
// and do the batch work with the GIL released.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include <fmt/format.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <sglab/registry.hpp>

#include "common/args.hpp"
#include "common/io.hpp"
#include "envmap/envmap.hpp"
#include "export/shader_export.hpp"
#include "python/gradient.hpp"
#include "reference/reference.hpp"
#include "reference/scene.hpp"

namespace py = pybind11;

namespace sglab::python {
namespace {

// The reference engine answers in chunks with its cache emptied after each,
// so memory stays bounded whatever the array's size.
constexpr std::size_t kReferenceChunk = 65536;

const Method& irradiance_method(const std::string& id) {
  if (const Method* m = find_method(irradiance_methods, id)) return *m;
  std::string known;
  for (const Method& each : irradiance_methods)
    known += (known.empty() ? "" : ", ") + std::string(each.id);
  throw io::InputError(fmt::format("unknown irradiance method '{}' (known: {})", id, known));
}

bool is_float32(const py::array& a) { return a.dtype().is(py::dtype::of<float>()); }
bool is_float64(const py::array& a) { return a.dtype().is(py::dtype::of<double>()); }

// kappa and cosine as the package passes them: C-contiguous, one shape,
// float32 or float64 each.
void check_pair(const py::array& kappa, const py::array& cosine) {
  for (const py::array* a : {&kappa, &cosine})
    if (!(is_float32(*a) || is_float64(*a)) || !(a->flags() & py::array::c_style))
      throw py::type_error("sglab._sglab: expected C-contiguous float32 or float64 arrays");
  if (kappa.ndim() != cosine.ndim() ||
      !std::equal(kappa.shape(), kappa.shape() + kappa.ndim(), cosine.shape()))
    throw py::value_error("sglab._sglab: kappa and cosine must have one shape");
}

std::vector<py::ssize_t> shape_of(const py::array& a) { return {a.shape(), a.shape() + a.ndim()}; }

// A float32 or float64 array's memory, read with the GIL held and used
// without it.
struct Column {
  const void* data;
  bool f32;
  std::size_t size;
  explicit Column(const py::array& a)
      : data(a.data()), f32(is_float32(a)), size(static_cast<std::size_t>(a.size())) {}
  double operator[](std::size_t i) const {
    return f32 ? static_cast<double>(static_cast<const float*>(data)[i])
               : static_cast<const double*>(data)[i];
  }
  // The values in T: the array's own memory when it is T, else a converted
  // copy in `storage`.
  template <class T>
  const T* as(std::vector<T>& storage) const {
    if (f32 == std::is_same_v<T, float>) return static_cast<const T*>(data);
    storage.resize(size);
    const auto convert = [&](const auto* from) {
      for (std::size_t i = 0; i < size; ++i) storage[i] = static_cast<T>(from[i]);
    };
    if (f32)
      convert(static_cast<const float*>(data));
    else
      convert(static_cast<const double*>(data));
    return storage.data();
  }
};

// The first point breaking io::point_error's rules, as the CLI's message with
// the flat index; nothing when every point is fine.
template <class K, class C>
std::optional<std::string> first_bad_point(const K* kappa, const C* cosine, std::size_t n,
                                           const io::NumberFormat* kappa_format) {
  for (std::size_t i = 0; i < n; ++i) {
    const auto k = static_cast<double>(kappa[i]), c = static_cast<double>(cosine[i]);
    if (!io::point_ok(k, c, kappa_format))
      return fmt::format("{} (at flat index {})", io::point_error(k, c, kappa_format), i);
  }
  return std::nullopt;
}

std::optional<std::string> first_bad_point(const Column& kappa, const Column& cosine,
                                           const io::NumberFormat* kappa_format) {
  // One loop per dtype pair, so the common case (both float32 or both
  // float64) is a tight loop.
  const auto run = [&](const auto* k) {
    return cosine.f32 ? first_bad_point(k, static_cast<const float*>(cosine.data), kappa.size,
                                        kappa_format)
                      : first_bad_point(k, static_cast<const double*>(cosine.data), kappa.size,
                                        kappa_format);
  };
  return kappa.f32 ? run(static_cast<const float*>(kappa.data))
                   : run(static_cast<const double*>(kappa.data));
}

template <class T>
py::array_t<T> evaluate(const Method& m, const py::array& kappa_array,
                        const py::array& cosine_array) {
  py::array_t<T> out(shape_of(kappa_array));
  T* o = out.mutable_data();
  const Column kappa(kappa_array), cosine(cosine_array);
  std::optional<std::string> bad;
  {
    py::gil_scoped_release release;
    bad = first_bad_point(kappa, cosine, std::is_same_v<T, float> ? &io::kFloatFormat : nullptr);
    if (!bad) {
      std::vector<T> ks, cs;
      const T* k = kappa.as(ks);
      const T* c = cosine.as(cs);
      if constexpr (std::is_same_v<T, float>)
        m.batch32(c, k, o, kappa.size);
      else
        m.batch64(c, k, o, kappa.size);
    }
  }
  if (bad) throw io::InputError(*bad);
  return out;
}

py::array irradiance(const std::string& method, const py::array& kappa, const py::array& cosine,
                     const std::string& precision) {
  check_pair(kappa, cosine);
  const Method& m = irradiance_method(method);
  if (precision == "float") return evaluate<float>(m, kappa, cosine);
  if (precision == "double") return evaluate<double>(m, kappa, cosine);
  throw io::InputError(fmt::format("precision must be float or double; got '{}'", precision));
}

py::tuple irradiance_grad(const std::string& method, const py::array& kappa,
                          const py::array& cosine) {
  check_pair(kappa, cosine);
  const Method& m = irradiance_method(method);
  const GradientBatch gradient =
      gradient_batch(static_cast<std::size_t>(&m - &irradiance_methods[0]));
  const auto shape = shape_of(kappa);
  py::array_t<double> value(shape), d_kappa(shape), d_cosine(shape);
  double *v = value.mutable_data(), *dk = d_kappa.mutable_data(), *dc = d_cosine.mutable_data();
  const Column kc(kappa), cc(cosine);
  std::optional<std::string> bad;
  {
    py::gil_scoped_release release;
    bad = first_bad_point(kc, cc, nullptr);
    if (!bad) {
      std::vector<double> ks, cs;
      const double* k = kc.as(ks);
      const double* c = cc.as(cs);
      m.batch64(c, k, v, kc.size);
      gradient(c, k, dk, dc, kc.size);
    }
  }
  if (bad) throw io::InputError(*bad);
  return py::make_tuple(value, d_kappa, d_cosine);
}

py::array_t<double> reference(const py::array& kappa, const py::array& cosine,
                              const std::string& quantity) {
  check_pair(kappa, cosine);
  double reference::ReferencePoint::*field = nullptr;
  if (quantity == "irradiance")
    field = &reference::ReferencePoint::irradiance;
  else if (quantity == "hemispherical")
    field = &reference::ReferencePoint::hemispherical;
  else if (quantity == "normalized")
    field = &reference::ReferencePoint::normalized;
  else
    throw io::InputError(fmt::format(
        "quantity must be irradiance, hemispherical or normalized; got '{}'", quantity));
  py::array_t<double> out(shape_of(kappa));
  double* o = out.mutable_data();
  const Column kc(kappa), cc(cosine);
  const std::size_t n = kc.size;
  std::optional<std::string> bad;
  {
    py::gil_scoped_release release;
    bad = first_bad_point(kc, cc, nullptr);
    if (!bad) {
      reference::ReferenceEngine engine;
      std::vector<reference::Query> queries;
      for (std::size_t start = 0; start < n; start += kReferenceChunk) {
        const std::size_t end = std::min(n, start + kReferenceChunk);
        queries.clear();
        for (std::size_t i = start; i < end; ++i) queries.push_back({kc[i], cc[i]});
        const auto points = engine.evaluate(queries);
        for (std::size_t i = start; i < end; ++i) o[i] = points[i - start].*field;
        engine.clear_cache();
      }
    }
  }
  if (bad) throw io::InputError(*bad);
  return out;
}

py::list methods() {
  const auto exportable = shader::exportable_methods();
  const auto split = shader::split_methods();
  const auto has = [](const std::vector<std::string>& list, std::string_view id) {
    return std::find(list.begin(), list.end(), id) != list.end();
  };
  py::list out;
  for (const Method& m : irradiance_methods) {
    py::dict d;
    d["id"] = std::string(m.id);
    d["origin"] = std::string(to_string(m.origin));
    d["source"] = std::string(m.source);
    d["constants"] = std::string(m.constants);
    d["per_light_split"] = m.light_setup32 != nullptr;
    d["export"] = has(exportable, m.id);
    d["export_split"] = has(split, m.id);
    // Every exportable method has a half (binary16) GLSL and HLSL export.
    d["export_half"] = has(exportable, m.id);
    out.append(d);
  }
  return out;
}

std::string export_method(const std::string& method, const std::string& lang,
                          const std::string& precision, bool split) {
  const auto l = io::parse_option<io::Language>("lang", lang);
  const auto p =
      io::parse_option("precision", precision, {io::Precision::float32, io::Precision::float16});
  shader::ExportRequest req = shader::standard_request(l, method, p);
  req.split = split;
  if (split) req.command += " --split";
  try {
    return shader::export_source(req).source;
  } catch (const std::invalid_argument& e) {
    throw io::InputError(e.what());
  }
}

// ---- environment maps --------------------------------------------------------

envmap::Map map_from_array(const py::array_t<float, py::array::c_style>& rgb) {
  if (rgb.ndim() != 3 || rgb.shape(2) != 3)
    throw io::InputError(fmt::format(
        "envmap array: expected shape (height, width, 3), got {} dimensions{}", rgb.ndim(),
        rgb.ndim() == 3 ? fmt::format(" with {} channels", rgb.shape(2)) : ""));
  envmap::check_size(static_cast<std::uint64_t>(rgb.shape(1)),
                     static_cast<std::uint64_t>(rgb.shape(0)), "envmap array");
  envmap::Map map;
  map.height = static_cast<std::size_t>(rgb.shape(0));
  map.width = static_cast<std::size_t>(rgb.shape(1));
  map.rgb.assign(rgb.data(), rgb.data() + rgb.size());
  envmap::check_map(map, "envmap array");
  return map;
}

std::vector<reference::Vec3> vectors_from(const py::array_t<double, py::array::c_style>& a,
                                          const char* name) {
  if (a.ndim() != 2 || a.shape(1) != 3)
    throw io::InputError(fmt::format("{}: expected shape (n, 3)", name));
  std::vector<reference::Vec3> out(static_cast<std::size_t>(a.shape(0)));
  std::memcpy(out.data(), a.data(), out.size() * sizeof(reference::Vec3));
  return out;
}

// Unit normals: each row divided by its length; a zero or non-finite row is refused.
std::vector<reference::Vec3> normals_from(const py::array_t<double, py::array::c_style>& a,
                                          const char* name = "normals") {
  auto normals = vectors_from(a, name);
  for (std::size_t i = 0; i < normals.size(); ++i) {
    auto& n = normals[i];
    const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(std::isfinite(len) && len > 0))
      throw io::InputError(fmt::format("{}[{}]: ({}, {}, {}) is not a nonzero finite vector", name,
                                       i, n[0], n[1], n[2]));
    // Rows of unit length up to rounding are kept as they are (so the CLI's
    // Fibonacci normals give the CLI's values); others are divided by it.
    if (std::abs(len - 1) > 4 * std::numeric_limits<double>::epsilon())
      for (double& x : n) x /= len;
  }
  return normals;
}

py::array_t<double> vectors_to(const std::vector<reference::Vec3>& v) {
  py::array_t<double> out({static_cast<py::ssize_t>(v.size()), py::ssize_t{3}});
  std::memcpy(out.mutable_data(), v.data(), v.size() * sizeof(reference::Vec3));
  return out;
}

py::array_t<float> map_rgb(const envmap::Map& map) {
  py::array_t<float> out(
      {static_cast<py::ssize_t>(map.height), static_cast<py::ssize_t>(map.width), py::ssize_t{3}});
  std::memcpy(out.mutable_data(), map.rgb.data(), map.rgb.size() * sizeof(float));
  return out;
}

py::dict lobes_dict(const std::vector<envmap::Lobe>& lobes) {
  std::vector<reference::Vec3> axis, amplitude;
  py::array_t<double> sharpness(static_cast<py::ssize_t>(lobes.size()));
  for (std::size_t k = 0; k < lobes.size(); ++k) {
    axis.push_back(lobes[k].axis);
    amplitude.push_back(lobes[k].amplitude);
    sharpness.mutable_data()[k] = lobes[k].sharpness;
  }
  py::dict d;
  d["axis"] = vectors_to(axis);
  d["sharpness"] = sharpness;
  d["amplitude"] = vectors_to(amplitude);
  return d;
}

std::vector<envmap::Lobe> lobes_from(const py::array_t<double, py::array::c_style>& axis,
                                     const py::array_t<double, py::array::c_style>& sharpness,
                                     const py::array_t<double, py::array::c_style>& amplitude) {
  const auto axes = vectors_from(axis, "axis");
  const auto amps = vectors_from(amplitude, "amplitude");
  if (sharpness.ndim() != 1 || static_cast<std::size_t>(sharpness.shape(0)) != axes.size() ||
      amps.size() != axes.size())
    throw io::InputError(fmt::format(
        "lobes: axis (n, 3), sharpness (n,) and amplitude (n, 3) must have one n; got {}, {}, {}",
        axes.size(), sharpness.ndim() == 1 ? sharpness.shape(0) : -1, amps.size()));
  std::vector<envmap::Lobe> lobes;
  for (std::size_t k = 0; k < axes.size(); ++k) {
    const double kappa = sharpness.data()[k];
    if (!(std::isfinite(kappa) && kappa >= 0))
      throw io::InputError(fmt::format("sharpness[{}] must be finite and >= 0, got {}", k, kappa));
    for (double a : amps[k])
      if (!std::isfinite(a)) throw io::InputError(fmt::format("amplitude[{}] must be finite", k));
    lobes.push_back({axes[k], kappa, amps[k]});
  }
  // Unit axes, as normals are.
  const auto unit = normals_from(axis, "axis");
  for (std::size_t k = 0; k < lobes.size(); ++k) lobes[k].axis = unit[k];
  return lobes;
}

py::dict fit(const envmap::Map& map, std::size_t lobes, const std::string& objective,
             std::size_t fit_normals, int max_iterations) {
  envmap::FitOptions options;
  options.lobes = lobes;
  options.fit_normals = fit_normals;
  options.max_iterations = max_iterations;
  if (objective == "radiance")
    options.objective = envmap::Objective::radiance;
  else if (objective == "irradiance")
    options.objective = envmap::Objective::irradiance;
  else
    throw io::InputError(
        fmt::format("objective: expected radiance or irradiance, got '{}'", objective));
  envmap::FitReport report;
  {
    py::gil_scoped_release release;
    // As `sglab envmap fit`: the working copy, the exact irradiance of the
    // full map at the fit's Fibonacci normals, then the fit.
    const envmap::Map work = envmap::working_copy(map);
    envmap::check_lobe_count(work, lobes);
    const auto exact = envmap::irradiance(map, reference::fibonacci_normals(options.fit_normals));
    report = envmap::fit(work, exact, options);
  }
  py::dict d = lobes_dict(report.lobes);
  d["iterations"] = report.iterations;
  d["converged"] = report.converged;
  return d;
}

void bind_envmap(py::module_& parent) {
  py::module_ m = parent.def_submodule("envmap", "HDR environment maps (sglab envmap)");
  py::class_<envmap::Map>(m, "Map", "An equirectangular RGB radiance map (docs/envmaps.md)")
      .def_property_readonly("width", [](const envmap::Map& map) { return map.width; })
      .def_property_readonly("height", [](const envmap::Map& map) { return map.height; })
      .def_property_readonly("rgb", &map_rgb, "a copy of the radiance, shape (height, width, 3)");
  m.def(
      "read", [](const std::string& path) { return envmap::read_map(path); }, py::arg("path"),
      py::call_guard<py::gil_scoped_release>());
  m.def("from_array", &map_from_array, py::arg("rgb"));
  m.def(
      "irradiance",
      [](const envmap::Map& map, const py::array_t<double, py::array::c_style>& normals) {
        const auto n = normals_from(normals);
        std::vector<reference::Vec3> e;
        {
          py::gil_scoped_release release;
          e = envmap::irradiance(map, n);
        }
        return vectors_to(e);
      },
      py::arg("map"), py::arg("normals"));
  m.def("fit", &fit, py::arg("map"), py::arg("lobes"), py::arg("objective"), py::arg("fit_normals"),
        py::arg("max_iterations"));
  m.def(
      "lobes_irradiance",
      [](const py::array_t<double, py::array::c_style>& axis,
         const py::array_t<double, py::array::c_style>& sharpness,
         const py::array_t<double, py::array::c_style>& amplitude,
         const py::array_t<double, py::array::c_style>& normals) {
        const auto lobes = lobes_from(axis, sharpness, amplitude);
        const auto n = normals_from(normals);
        try {
          reference::check_scene_limits(lobes.size(), n.size());
        } catch (const reference::SceneError& e) {
          throw io::InputError(e.what());
        }
        std::vector<reference::Vec3> e;
        {
          py::gil_scoped_release release;
          e = envmap::lobes_irradiance_exact(lobes, n);
        }
        return vectors_to(e);
      },
      py::arg("axis"), py::arg("sharpness"), py::arg("amplitude"), py::arg("normals"));
  m.def(
      "fibonacci_normals",
      [](std::size_t n) { return vectors_to(reference::fibonacci_normals(n)); }, py::arg("n"));
}

}  // namespace
}  // namespace sglab::python

PYBIND11_MODULE(_sglab, m) {
  using namespace sglab;
  using namespace sglab::python;
  m.doc() = "sglab's runtime, gradients, reference engine, export and envmaps (python/module.cpp)";
  // Bad input (the CLI's exit 2) is sglab.InputError, a ValueError.
  py::register_exception<io::InputError>(m, "InputError", PyExc_ValueError);
  m.def("methods", &methods);
  m.def("irradiance", &irradiance, py::arg("method"), py::arg("kappa"), py::arg("cosine"),
        py::arg("precision"));
  m.def("irradiance_grad", &irradiance_grad, py::arg("method"), py::arg("kappa"),
        py::arg("cosine"));
  m.def("reference", &python::reference, py::arg("kappa"), py::arg("cosine"), py::arg("quantity"));
  m.def("export", &export_method, py::arg("method"), py::arg("lang"), py::arg("precision"),
        py::arg("split"));
  // The registry's float batch alone on float32 arrays of one size (no checks,
  // no conversion, no broadcasting): what sglab.irradiance(..., "float")
  // must equal, and the baseline of bench/python_irradiance.py.
  m.def("_batch32",
        [](const std::string& method, const py::array_t<float, py::array::c_style>& kappa,
           const py::array_t<float, py::array::c_style>& cosine) {
          const Method& meth = irradiance_method(method);
          if (kappa.size() != cosine.size()) throw py::value_error("_batch32: one size please");
          py::array_t<float> out(kappa.size());
          const float *k = kappa.data(), *c = cosine.data();
          float* o = out.mutable_data();
          py::gil_scoped_release release;
          meth.batch32(c, k, o, static_cast<std::size_t>(kappa.size()));
          return out;
        });
  bind_envmap(m);
}
