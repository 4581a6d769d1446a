#include "aa/signature.h"

#include <algorithm>

#include "core/error.h"

namespace zz {

namespace {

struct NamedPart {
  std::string_view name;
  unsigned part;
};
constexpr NamedPart kParts[] = {
    {"object", kSignatureObject}, {"lights", kSignatureLights}, {"secondary", kSignatureSecondary}};

}  // namespace

unsigned parse_signature(std::string_view text) {
  if (text == "none") return kSignatureNone;
  if (text == "all") return kSignatureAll;
  unsigned parts = 0;
  size_t start = 0;
  while (start <= text.size()) {
    const size_t comma = std::min(text.find(',', start), text.size());
    const std::string_view name = text.substr(start, comma - start);
    bool known = false;
    for (const NamedPart& p : kParts)
      if (name == p.name) parts |= p.part, known = true;
    if (!known)
      throw Error("unknown signature part '" + std::string(name) +
                  "' (expected none, all, or a comma list of object, lights, secondary)");
    start = comma + 1;
  }
  return parts;
}

std::string signature_name(unsigned parts) {
  parts &= kSignatureAll;
  if (parts == kSignatureNone) return "none";
  if (parts == kSignatureAll) return "all";
  std::string name;
  for (const NamedPart& p : kParts) {
    if (!(parts & p.part)) continue;
    if (!name.empty()) name += ',';
    name += p.name;
  }
  return name;
}

}  // namespace zz
