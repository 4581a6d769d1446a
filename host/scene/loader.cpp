// load_scene(): dispatch by extension, the JSON scene rig (format in scenes/README.md),
// and the automatic framing camera.
#include "scene/loader.h"

#include <nlohmann/json.hpp>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cerrno>
#include <cctype>
#include <cstring>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <initializer_list>
#include <limits>
#include <vector>
#include <optional>
#include <set>
#include <string>
#include <utility>

#include "core/error.h"
#include "core/file_io.h"
#include "scene/animation.h"
#include "scene/gltf_file.h"

namespace zz {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

// ---- strict JSON field access: wrong types and unknown keys are errors -----------------
struct Json {
  const std::string& file;

  [[noreturn]] void fail(const std::string& msg) const { throw Error(file + ": " + msg); }

  void check_keys(const json& obj, std::initializer_list<const char*> allowed, const std::string& where) const {
    if (!obj.is_object()) fail(where + " must be an object");
    for (auto it = obj.begin(); it != obj.end(); ++it) {
      bool ok = std::any_of(allowed.begin(), allowed.end(), [&](const char* k) { return it.key() == k; });
      if (!ok) fail("unknown key '" + it.key() + "' in " + where);
    }
  }
  float number(const json& v, const std::string& what) const {
    if (!v.is_number()) fail(what + " must be a number");
    double d = v.get<double>();
    if (!std::isfinite(d) || std::abs(d) > 1e30) fail(what + " must be a finite number within +-1e30");
    return float(d);
  }
  int integer(const json& v, const std::string& what, int lo, int hi) const {
    if (!v.is_number_integer()) fail(what + " must be an integer");
    auto i = v.get<int64_t>();
    if (i < lo || i > hi) fail(what + " must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return int(i);
  }
  bool boolean(const json& v, const std::string& what) const {
    if (!v.is_boolean()) fail(what + " must be true or false");
    return v.get<bool>();
  }
  std::string string(const json& v, const std::string& what) const {
    if (!v.is_string()) fail(what + " must be a string");
    return v.get<std::string>();
  }
  glm::vec3 vec3(const json& v, const std::string& what) const {
    if (!v.is_array() || v.size() != 3) fail(what + " must be an array of 3 numbers");
    return {number(v[0], what), number(v[1], what), number(v[2], what)};
  }
  // A colour or scale: one number (grey / uniform) or three.
  glm::vec3 vec3_or_scalar(const json& v, const std::string& what) const {
    return v.is_number() ? glm::vec3(number(v, what)) : vec3(v, what);
  }
};

glm::mat4 parse_transform(const Json& J, const json& t) {
  J.check_keys(t, {"matrix", "scale", "rotate_y_deg", "translate"}, "transform");
  if (t.contains("matrix")) {
    const json& m = t["matrix"];
    if (!m.is_array() || m.size() != 16) J.fail("transform.matrix must be 16 numbers (column-major, as glTF)");
    if (t.size() != 1) J.fail("transform.matrix cannot be combined with scale/rotate/translate");
    glm::mat4 out;
    for (int i = 0; i < 16; ++i) glm::value_ptr(out)[i] = J.number(m[size_t(i)], "transform.matrix");
    return out;
  }
  // model = translate * rotate_y * scale (scale first, as glTF's TRS).
  glm::mat4 out(1.0f);
  if (t.contains("translate")) out = glm::translate(out, J.vec3(t["translate"], "transform.translate"));
  if (t.contains("rotate_y_deg"))
    out = glm::rotate(out, glm::radians(J.number(t["rotate_y_deg"], "transform.rotate_y_deg")), glm::vec3(0, 1, 0));
  if (t.contains("scale")) out = glm::scale(out, J.vec3_or_scalar(t["scale"], "transform.scale"));
  return out;
}

Camera parse_camera(const Json& J, const json& c, const std::string& where) {
  J.check_keys(c, {"name", "eye", "target", "up", "yfov_deg", "ymag", "aspect", "znear", "zfar"}, where);
  if (!c.contains("eye") || !c.contains("target")) J.fail(where + " needs \"eye\" and \"target\"");
  glm::vec3 eye = J.vec3(c["eye"], where + ".eye");
  glm::vec3 target = J.vec3(c["target"], where + ".target");
  glm::vec3 up = c.contains("up") ? J.vec3(c["up"], where + ".up") : glm::vec3(0, 1, 0);
  float yfov_deg = c.contains("yfov_deg") ? J.number(c["yfov_deg"], where + ".yfov_deg") : 45.0f;
  if (!valid_yfov_degrees(yfov_deg)) J.fail(where + ".yfov_deg must be in (0.1, 179)");
  const glm::vec3 f = target - eye;
  // Compared as unit vectors: |f|^2 of a camera 1e19 from its target overflows.
  const std::optional<glm::vec3> forward = unit_direction(f), up_unit = unit_direction(up);
  if (!forward || !up_unit || glm::length(glm::cross(*forward, *up_unit)) <= 1e-6f)
    J.fail(where + ": eye equals target or up is parallel to the view direction");
  Camera cam = Camera::look_at(eye, target, up, glm::radians(yfov_deg));
  cam.name = c.contains("name") ? J.string(c["name"], where + ".name") : "rig";
  if (c.contains("ymag")) {  // orthographic: the view's half height, in world units
    if (c.contains("yfov_deg")) J.fail(where + " has both yfov_deg (perspective) and ymag (orthographic)");
    cam.ymag = J.number(c["ymag"], where + ".ymag");
    if (!(cam.ymag > 0.0f) || !std::isfinite(cam.ymag)) J.fail(where + ".ymag must be a finite half height > 0");
  }
  if (c.contains("aspect")) {
    cam.aspect = J.number(c["aspect"], where + ".aspect");
    if (!(cam.aspect > 0.0f)) J.fail(where + ".aspect must be > 0 (width / height)");
  }
  // Clipping planes (depths along the view direction): none unless asked for.
  if (c.contains("znear")) {
    cam.znear = J.number(c["znear"], where + ".znear");
    if (!(cam.znear >= 0.0f) || !std::isfinite(cam.znear)) J.fail(where + ".znear must be a finite depth >= 0");
  }
  if (c.contains("zfar")) {
    cam.zfar = J.number(c["zfar"], where + ".zfar");
    if (!(cam.zfar > cam.znear)) J.fail(where + ".zfar must be greater than znear");
  }
  return cam;
}

Light parse_light(const Json& J, const json& l, const std::string& where) {
  J.check_keys(l, {"type", "name", "position", "direction", "color", "intensity", "range",
                   "inner_cone_deg", "outer_cone_deg"}, where);
  Light out;
  std::string type = l.contains("type") ? J.string(l["type"], where + ".type") : "point";
  if (type == "point") out.type = Light::Type::Point;
  else if (type == "spot") out.type = Light::Type::Spot;
  else if (type == "directional") out.type = Light::Type::Directional;
  else J.fail(where + ".type must be point, spot or directional");
  if (out.type != Light::Type::Directional) {
    if (!l.contains("position")) J.fail(where + " needs \"position\"");
    out.position = J.vec3(l["position"], where + ".position");
  }
  if (out.type != Light::Type::Point) {
    if (!l.contains("direction")) J.fail(where + " needs \"direction\"");
    const std::optional<glm::vec3> d = unit_direction(J.vec3(l["direction"], where + ".direction"));
    if (!d) J.fail(where + ".direction must be non-zero");
    out.direction = *d;
  }
  out.name = l.contains("name") ? J.string(l["name"], where + ".name") : where;
  glm::vec3 color = l.contains("color") ? J.vec3_or_scalar(l["color"], where + ".color") : glm::vec3(1.0f);
  float intensity = l.contains("intensity") ? J.number(l["intensity"], where + ".intensity") : 1.0f;
  out.intensity = color * intensity;
  if (!std::isfinite(out.intensity.x) || !std::isfinite(out.intensity.y) || !std::isfinite(out.intensity.z))
    J.fail(where + ": color * intensity overflows");
  if (l.contains("range")) out.range = J.number(l["range"], where + ".range");
  // KHR_lights_punctual's range of cone angles: 0 <= inner, outer <= 90 degrees.
  for (const auto& [key, angle] : {std::pair{"inner_cone_deg", &out.inner_cone}, std::pair{"outer_cone_deg", &out.outer_cone}})
    if (l.contains(key)) {
      const float degrees = J.number(l[key], where + "." + key);
      if (!(degrees >= 0.0f && degrees <= 90.0f)) J.fail(where + "." + key + " must be in [0, 90] degrees");
      *angle = glm::radians(degrees);
    }
  if (const std::string problem = light_problem(out); !problem.empty()) J.fail(where + ": " + problem);
  return out;
}

void apply_material_override(const Json& J, Material& m, const json& o, const std::string& where) {
  J.check_keys(o, {"base_color", "metallic", "roughness", "transmission", "ior", "emissive", "thickness",
                   "attenuation_color", "attenuation_distance", "double_sided"}, where);
  if (o.contains("base_color")) m.base_color = J.vec3_or_scalar(o["base_color"], where + ".base_color");
  if (o.contains("metallic")) m.metallic = J.number(o["metallic"], where + ".metallic");
  if (o.contains("roughness")) m.roughness = J.number(o["roughness"], where + ".roughness");
  if (o.contains("transmission")) m.transmission = J.number(o["transmission"], where + ".transmission");
  if (o.contains("ior")) m.ior = J.number(o["ior"], where + ".ior");
  if (o.contains("emissive")) m.emissive = J.vec3_or_scalar(o["emissive"], where + ".emissive");
  if (o.contains("thickness")) m.thickness = J.number(o["thickness"], where + ".thickness");
  if (o.contains("attenuation_color"))
    m.attenuation_color = J.vec3_or_scalar(o["attenuation_color"], where + ".attenuation_color");
  if (o.contains("attenuation_distance"))
    m.attenuation_distance = J.number(o["attenuation_distance"], where + ".attenuation_distance");
  if (o.contains("double_sided")) m.double_sided = J.boolean(o["double_sided"], where + ".double_sided");
}

// When the scene is posed: the frame clock of LoadOptions and the rig's "fps"/"frames".
struct FrameClock {
  double fps = kDefaultFps;
  std::optional<std::pair<int, int>> rig_frames;
  double time = 0.0;
  int frame = 0;

  FrameClock(const LoadOptions& options, double rig_fps, std::optional<std::pair<int, int>> frames)
      : rig_frames(frames) {
    fps = options.fps > 0.0 ? options.fps : rig_fps > 0.0 ? rig_fps : kDefaultFps;
    if (options.time) {
      // A time on a frame is that frame's time, exactly: its output is named after the
      // frame, and a time within 1e-6 of it posed the scene a hair off the --frame render
      // of the same name. It stays a --time (warnings speak of the animation's end).
      const std::optional<int> on = frame_at(*options.time, fps);
      frame = -1;
      time = on ? double(*on) / fps : *options.time;
    } else {
      frame = options.frame ? *options.frame : rig_frames ? rig_frames->first : 0;
      time = double(frame) / fps;
    }
  }
  LoadOptions posed(const LoadOptions& options) const {
    LoadOptions o = options;
    o.time = time;
    return o;
  }
  void apply(Scene& scene) const {
    scene.fps = fps;
    scene.time = time;
    scene.frame = frame;
    scene.first_frame = rig_frames ? rig_frames->first : 0;
    scene.last_frame = rig_frames ? rig_frames->second : zz::last_frame(scene.animation_end, fps);
  }
};

fs::path assets_root(const fs::path& json_dir, const LoadOptions& options) {
  if (!options.assets_dir.empty()) return options.assets_dir;
  if (const char* env = std::getenv("ZIGZAG_ASSETS"); env && *env) return fs::path(env);
  // Rigs live in <repo>/scenes/; the shared assets sit next to the checkout.
  return (json_dir / ".." / ".." / "shared" / "scenes").lexically_normal();
}

// "line:column" of the 1-based byte offset `byte` in `text` (nlohmann's parse_error::byte).
std::string json_line_column(const std::string& text, size_t byte) {
  size_t line = 1, column = 1;
  for (size_t i = 0; i + 1 < byte && i < text.size(); ++i) {
    if (text[i] == '\n') ++line, column = 1;
    else ++column;
  }
  return std::to_string(line) + ":" + std::to_string(column);
}

// "file:line:column: invalid JSON: what", the position from the parser's byte offset.
[[noreturn]] void throw_json_error(const std::string& file, const std::string& text, size_t byte, std::string what) {
  // nlohmann's text: "[json.exception.parse_error.101] parse error at line 1, column 2: syntax error ...".
  if (const size_t colon = what.find(": ", what.find("column")); colon != std::string::npos) what = what.substr(colon + 2);
  std::replace(what.begin(), what.end(), '\n', ' ');
  throw Error(file + ":" + json_line_column(text, byte) + ": invalid JSON: " + what);
}

// Says so where nothing could light the image: no light that can reach anything (a rig
// gets no default lights, scenes/README.md; a glTF's lights may all be black or closed
// spots), no emissive material and a black background.
void warn_if_nothing_lights(const Scene& scene, const std::string& file, const LoadOptions& options) {
  if (options.quiet || std::any_of(scene.lights.begin(), scene.lights.end(), can_light) ||
      scene.effects().emission || glm::any(glm::greaterThan(scene.background, glm::vec3(0.0f))))
    return;
  std::fprintf(stderr, "warning: %s: %s, no emissive material and a black background: the image will be black%s\n",
               file.c_str(),
               scene.lights.empty() ? "no lights" : "no light with an intensity above 0 (and an open spot cone)",
               scene.lights.empty() ? " (add \"lights\" to the rig, see scenes/README.md)" : "");
}

// Where `number` first stands as a number in JSON `text` (not inside a string, nor part of
// a longer number); npos if nowhere.
size_t find_json_number(const std::string& text, const std::string& number) {
  if (number.empty()) return std::string::npos;
  const auto in_number = [](char c) { return std::isdigit(static_cast<unsigned char>(c)) || std::strchr("+-.eE", c); };
  bool in_string = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\') ++i;  // the escaped character
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (text.compare(i, number.size(), number) == 0 && (i == 0 || !in_number(text[i - 1])) &&
               (i + number.size() == text.size() || !in_number(text[i + number.size()]))) {
      return i;
    }
  }
  return std::string::npos;
}

// Where the n-th (from 0) object key of JSON `text` starts (its opening quote): a string
// followed by a colon; npos if there are fewer. Keys come in the order the parser reports them.
size_t find_json_key(const std::string& text, size_t n) {
  size_t start = 0;
  bool in_string = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\') {
        ++i;  // the escaped character
      } else if (c == '"') {
        in_string = false;
        const size_t next = text.find_first_not_of(" \t\r\n", i + 1);
        if (next != std::string::npos && text[next] == ':' && n-- == 0) return start;
      }
    } else if (c == '"') {
      in_string = true;
      start = i;
    }
  }
  return std::string::npos;
}

constexpr uintmax_t kMaxRigBytes = uintmax_t(64) << 20;

// Refuses a key given twice in one object, naming where ("lights[2]"): nlohmann keeps the
// last, so a repeated "exposure" or "lights" silently replaced the first, against the rule
// that a rig never falls back without a word (its unknown keys are refused too).
class UniqueKeys {
 public:
  UniqueKeys(std::string file, const std::string& text) : file_(std::move(file)), text_(text) {}
  bool operator()(int /*depth*/, json::parse_event_t event, json& parsed) {
    switch (event) {
      case json::parse_event_t::object_start:
      case json::parse_event_t::array_start:
        frames_.push_back({event == json::parse_event_t::object_start, {}, {}, 0, child_label()});
        break;
      case json::parse_event_t::key: {
        Frame& object = frames_.back();
        object.last_key = parsed.get<std::string>();
        if (!object.keys.insert(object.last_key).second) {
          const size_t at = find_json_key(text_, keys_seen_);
          throw Error(file_ + (at == std::string::npos ? "" : ":" + json_line_column(text_, at + 1)) + ": " +
                      (path().empty() ? "" : path() + ": ") + "key \"" + object.last_key +
                      "\" given twice (one value per key)");
        }
        ++keys_seen_;
        break;
      }
      case json::parse_event_t::value:
        if (!frames_.empty() && !frames_.back().object) ++frames_.back().index;
        break;
      case json::parse_event_t::object_end:
      case json::parse_event_t::array_end:
        frames_.pop_back();
        if (!frames_.empty() && !frames_.back().object) ++frames_.back().index;
        break;
    }
    return true;
  }

 private:
  struct Frame {
    bool object;
    std::set<std::string> keys;
    std::string last_key;
    size_t index;
    std::string label;  // how its parent reaches it: "lights" or "[2]"
  };
  std::string child_label() const {
    if (frames_.empty()) return "";
    const Frame& parent = frames_.back();
    return parent.object ? parent.last_key : "[" + std::to_string(parent.index) + "]";
  }
  std::string path() const {
    std::string p;
    for (const Frame& f : frames_) p += f.label.empty() || f.label[0] == '[' || p.empty() ? f.label : "." + f.label;
    return p;
  }
  std::string file_;
  const std::string& text_;
  size_t keys_seen_ = 0;  // keys parsed so far, this one excluded: the index find_json_key takes
  std::vector<Frame> frames_;
};

json parse_rig_file(const fs::path& path) {
  const std::string file = path.string();
  // Not a device or a pipe (a rig linked to /dev/zero read until memory ran out).
  const std::vector<unsigned char> bytes = read_regular_file(file, kMaxRigBytes);
  const std::string text(bytes.begin(), bytes.end());
  if (text.find_first_not_of(" \t\r\n") == std::string::npos)
    throw Error(file + ":1:1: invalid JSON: the file is empty");
  try {
    return json::parse(text, UniqueKeys(file, text));
  } catch (const json::parse_error& e) {
    throw_json_error(file, text, e.byte, e.what());
  } catch (const json::exception& e) {
    // "[json.exception.out_of_range.406] number overflow parsing '1e400'": no byte offset
    // (review: reported at 1:1), so the position is where it first stands as a number.
    std::string what = e.what();
    if (const size_t bracket = what.find("] "); what.rfind("[json.", 0) == 0 && bracket != std::string::npos)
      what = what.substr(bracket + 2);
    const size_t open = what.find("parsing '");
    const size_t close = open == std::string::npos ? open : what.find('\'', open + 9);
    const size_t at = close == std::string::npos ? std::string::npos : find_json_number(text, what.substr(open + 9, close - open - 9));
    throw_json_error(file, text, at == std::string::npos ? 0 : at + 1, what);
  }
}

// A rig's model must be a glTF. When it names another rig, follow the chain to say why
// that cannot load: a cycle (the chain named) or a rig of a rig.
[[noreturn]] void reject_rig_model(const fs::path& rig, const fs::path& model) {
  std::vector<fs::path> chain = {fs::weakly_canonical(rig)};
  std::string text = rig.string();
  fs::path next = model;
  for (int hops = 0; hops < 64; ++hops) {
    const fs::path canonical = fs::weakly_canonical(next);
    text += " -> " + next.lexically_normal().string();
    if (std::find(chain.begin(), chain.end(), canonical) != chain.end())
      throw Error(rig.string() + ": rig cycle: " + text + " (a rig's \"model\" must be a .gltf or .glb)");
    chain.push_back(canonical);
    const std::string ext = lowercase_extension(next);
    std::error_code ec;
    if (ext != ".json" || !fs::is_regular_file(next, ec)) break;
    json j;
    try {
      j = parse_rig_file(next);
    } catch (const Error&) {
      break;
    }
    if (!j.is_object() || !j.contains("model") || !j["model"].is_string()) break;
    next = next.parent_path() / j["model"].get<std::string>();
  }
  throw Error(rig.string() + ": model '" + model.string() + "' is a rig, not a .gltf or .glb (rigs do not nest)");
}

// Where a rig's "model" is: "assets:NAME/..." under the assets folder, else beside the rig.
fs::path rig_model_path(const fs::path& rig, const std::string& model, const LoadOptions& options) {
  const fs::path dir = rig.parent_path().empty() ? fs::path(".") : rig.parent_path();
  return model.rfind("assets:", 0) == 0 ? assets_root(dir, options) / model.substr(7) : dir / model;
}

Scene load_json_scene(const fs::path& path, const LoadOptions& options) {
  const std::string file = path.string();
  const json j = parse_rig_file(path);
  const Json J{file};
  J.check_keys(j, {"name", "description", "model", "transform", "camera", "cameras",
                   "use_model_cameras", "default_camera", "lights", "replace_lights", "background", "exposure",
                   "max_depth", "width", "height", "materials_override", "fps", "frames"}, "scene");
  if (!j.contains("model")) J.fail("missing \"model\"");
  double rig_fps = 0.0;
  if (j.contains("fps")) {
    rig_fps = J.number(j["fps"], "fps");
    if (!(rig_fps >= double(float(kMinFps)) && rig_fps <= kMaxFps)) J.fail("fps must be in [0.001, 1000]");
  }
  std::optional<std::pair<int, int>> rig_frames;
  if (j.contains("frames")) {
    const json& f = j["frames"];
    if (!f.is_array() || f.size() != 2) J.fail("frames must be [first, last] (two integers)");
    const int first = J.integer(f[0], "frames[0]", 0, 100000000), last = J.integer(f[1], "frames[1]", 0, 100000000);
    if (last < first) J.fail("frames: last (" + std::to_string(last) + ") is before first (" + std::to_string(first) + ")");
    rig_frames = std::make_pair(first, last);
  }
  const FrameClock clock(options, rig_fps, rig_frames);

  Scene scene;
  scene.source_files.push_back(file);
  scene.name = j.contains("name") ? J.string(j["name"], "name") : path.stem().string();
  const std::string model = J.string(j["model"], "model");
  const fs::path model_path = rig_model_path(path, model, options);
  std::error_code ec;
  if (model.rfind("assets:", 0) == 0) {
    if (!fs::is_regular_file(model_path, ec))
      throw Error("missing asset: " + model_path.string() + " (referenced by " + file +
                  "; set ZIGZAG_ASSETS or --assets to the folder holding the shared scenes)");
  } else {
    if (fs::path(model).extension() == ".json") reject_rig_model(path, model_path);
    if (fs::is_directory(model_path, ec)) J.fail("model '" + model_path.string() + "' is a directory, not a glTF file");
    if (!fs::is_regular_file(model_path, ec)) J.fail("model '" + model_path.string() + "' not found");
  }
  const glm::mat4 transform = j.contains("transform") ? parse_transform(J, j["transform"]) : glm::mat4(1.0f);
  load_gltf_into(scene, model_path, transform, clock.posed(options));
  clock.apply(scene);

  // Cameras: the rig's own first, then the model's (unless disabled).
  std::vector<Camera> model_cameras = std::move(scene.cameras);
  scene.cameras.clear();
  if (j.contains("camera")) scene.cameras.push_back(parse_camera(J, j["camera"], "camera"));
  if (j.contains("cameras")) {
    if (!j["cameras"].is_array()) J.fail("cameras must be an array");
    for (size_t i = 0; i < j["cameras"].size(); ++i)
      scene.cameras.push_back(parse_camera(J, j["cameras"][i], "cameras[" + std::to_string(i) + "]"));
  }
  bool use_model_cameras = j.contains("use_model_cameras") ? J.boolean(j["use_model_cameras"], "use_model_cameras") : true;
  if (use_model_cameras) scene.cameras.insert(scene.cameras.end(), model_cameras.begin(), model_cameras.end());
  if (j.contains("default_camera")) {
    // Moves the named camera to the front (cameras[0] is what renders by default).
    const std::string name = J.string(j["default_camera"], "default_camera");
    auto it = std::find_if(scene.cameras.begin(), scene.cameras.end(), [&](const Camera& c) { return c.name == name; });
    if (it == scene.cameras.end()) J.fail("default_camera: no camera named '" + name + "'");
    std::rotate(scene.cameras.begin(), it, it + 1);
  }
  if (scene.cameras.empty()) scene.cameras.push_back(auto_camera(scene));

  if (j.contains("replace_lights") && J.boolean(j["replace_lights"], "replace_lights")) scene.lights.clear();
  if (j.contains("lights")) {
    if (!j["lights"].is_array()) J.fail("lights must be an array");
    for (size_t i = 0; i < j["lights"].size(); ++i) {
      scene.lights.push_back(parse_light(J, j["lights"][i], "lights[" + std::to_string(i) + "]"));
      if (const std::string cone = spot_cone_warning(scene.lights.back()); !cone.empty() && !options.quiet)
        std::fprintf(stderr, "warning: %s: %s\n", path.string().c_str(), cone.c_str());
    }
  }

  if (j.contains("background")) {
    scene.background = J.vec3_or_scalar(j["background"], "background");
    if (glm::any(glm::lessThan(scene.background, glm::vec3(0.0f))))
      J.fail("background must not be negative (it is radiance)");
  }
  if (j.contains("exposure")) {
    scene.exposure = J.number(j["exposure"], "exposure");  // compared as the float it is ("1e-6" is just below)
    if (!(scene.exposure >= float(kMinExposure) && scene.exposure <= float(kMaxExposure)))
      J.fail("exposure must be in [1e-06, 1e+06]");
  }
  if (j.contains("max_depth")) scene.max_depth = J.integer(j["max_depth"], "max_depth", kMinTraceDepth, kMaxTraceDepth);
  if (j.contains("width")) scene.default_width = J.integer(j["width"], "width", 1, kMaxImageSide), scene.width_given = true;
  if (j.contains("height")) scene.default_height = J.integer(j["height"], "height", 1, kMaxImageSide), scene.height_given = true;

  if (j.contains("materials_override")) {
    const json& o = j["materials_override"];
    if (!o.is_object()) J.fail("materials_override must be an object keyed by material name");
    for (auto it = o.begin(); it != o.end(); ++it) {
      // The override's own values on a default material: out of glTF's ranges, an error.
      Material probe;
      apply_material_override(J, probe, it.value(), "materials_override." + it.key());
      if (const std::vector<FactorProblem> bad = out_of_range_factors(probe); !bad.empty())
        J.fail("materials_override." + it.key() + ": " + bad.front().what);
      bool found = false;
      for (Material& m : scene.materials)
        if (m.name == it.key()) {
          apply_material_override(J, m, it.value(), "materials_override." + it.key());
          found = true;
        }
      if (!found) J.fail("materials_override: no material named '" + it.key() + "'");
    }
  }
  require_triangles(scene, file);
  scene.finalize_materials();
  warn_if_nothing_lights(scene, file, options);
  return scene;
}

}  // namespace

void require_triangles(const Scene& scene, const std::string& file) {
  if (scene.triangle_count() == 0)
    throw Error(file + ": no triangles to render (the scene has no triangle meshes, or only degenerate ones)");
}

std::vector<Light> default_lights(const Camera& camera) {
  // Directional, so they light a model of any size the same: a headlight along the view
  // and a key light from above, right and in front of the model (towards the camera).
  Light headlight;
  headlight.type = Light::Type::Directional;
  headlight.name = "default headlight";
  headlight.direction = camera.forward;
  headlight.intensity = glm::vec3(1.0f);
  Light key;
  key.type = Light::Type::Directional;
  key.name = "default key";
  key.direction = -glm::normalize(0.5f * camera.right + 1.0f * camera.up - 0.6f * camera.forward);
  key.intensity = glm::vec3(2.0f);
  return {headlight, key};
}

Camera auto_camera(const Scene& scene, float yfov) {
  if (scene.positions.empty()) return Camera{};
  const auto [lo, hi] = scene.bounds();
  const glm::vec3 centre = 0.5f * (lo + hi);
  // Not below a few float steps at the centre, where the camera would round onto it; an
  // absolute floor of 1e-6 framed smaller scenes (the loader keeps triangles down to 1e-10)
  // a fraction of the frame wide.
  const float largest = std::max({std::abs(centre.x), std::abs(centre.y), std::abs(centre.z)});
  const float step = std::nextafter(largest, std::numeric_limits<float>::infinity()) - largest;
  const float radius = std::max({0.5f * glm::length(hi - lo), 64.0f * step, 1e-20f});
  // The bounding sphere just fits the vertical field of view: d = r / sin(fov / 2).
  const float dist = radius / std::sin(0.5f * yfov);
  const glm::vec3 dir = glm::normalize(glm::vec3(0.35f, 0.3f, 1.0f));
  Camera c = Camera::look_at(centre + dir * dist, centre, glm::vec3(0.0f, 1.0f, 0.0f), yfov);
  c.name = "auto";
  if (!std::isfinite(dist) || !std::isfinite(c.position.x) || !std::isfinite(c.position.y) ||
      !std::isfinite(c.position.z)) {
    Camera fallback;  // bounds beyond float range: any finite camera will do
    fallback.name = "auto";
    return fallback;
  }
  return c;
}

std::vector<std::string> scene_files(const std::filesystem::path& path, const LoadOptions& options) {
  std::vector<std::string> files = {path.string()};
  fs::path gltf = path;
  if (lowercase_extension(path) == ".json") {
    try {
      const json j = parse_rig_file(path);
      if (!j.is_object() || !j.contains("model") || !j["model"].is_string()) return files;
      gltf = rig_model_path(path, j["model"].get<std::string>(), options);
      files.push_back(gltf.string());
    } catch (const std::exception&) {
      return files;  // loading the rig says what is wrong with it
    }
  }
  try {
    for (const fs::path& f : gltf::external_files(gltf)) files.push_back(f.string());
  } catch (const std::exception&) {  // an allocation: loading says what is wrong
  }
  return files;
}

Scene load_scene(const std::filesystem::path& path, const LoadOptions& options) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw Error(path.string() + ": is a directory, not a scene file");
  const bool exists = fs::exists(path, ec);
  if (ec) throw Error(path.string() + ": " + ec.message());  // e.g. a folder on the way not searchable
  if (!exists) throw Error(path.string() + ": file not found");
  const std::string ext = lowercase_extension(path);
  if (ext == ".json") return load_json_scene(path, options);
  if (ext != ".gltf" && ext != ".glb")
    throw Error(path.string() + ": unknown scene format (expected .json, .gltf or .glb)");
  Scene scene;
  scene.name = path.stem().string();
  const FrameClock clock(options, 0.0, std::nullopt);
  load_gltf_into(scene, path, glm::mat4(1.0f), clock.posed(options));
  clock.apply(scene);
  require_triangles(scene, path.string());
  if (scene.cameras.empty()) scene.cameras.push_back(auto_camera(scene));
  if (scene.lights.empty()) {
    scene.lights = default_lights(scene.cameras[0]);
    if (!options.quiet)
      std::fprintf(stderr,
                   "warning: %s: no lights in the file; using a default headlight and key light "
                   "(add lights with a scene rig, see scenes/README.md)\n",
                   path.string().c_str());
  }
  scene.finalize_materials();
  warn_if_nothing_lights(scene, path.string(), options);
  return scene;
}

}  // namespace zz
