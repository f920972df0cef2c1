#include "cli/args.hpp"

#include <cmath>
#include <cstdlib>

namespace humandyn::cli {

Args::Args(std::vector<std::string> argv, const std::set<std::string>& flags) {
  for (std::size_t i = 0; i < argv.size(); ++i) {
    const std::string& a = argv[i];
    if (a.rfind("--", 0) == 0 && a.size() > 2) {
      if (flags.count(a)) {
        flags_set_.insert(a);
      } else if (const auto eq = a.find('='); eq != std::string::npos) {
        values_[a.substr(0, eq)].push_back(a.substr(eq + 1));
      } else {
        if (i + 1 >= argv.size()) throw UsageError("option " + a + " needs a value");
        values_[a].push_back(argv[++i]);
      }
    } else {
      positionals_.push_back(a);
    }
  }
}

bool Args::flag(const std::string& name) {
  used_.insert(name);
  return flags_set_.count(name) > 0;
}

std::optional<std::string> Args::get(const std::string& name) {
  used_.insert(name);
  const auto it = values_.find(name);
  if (it == values_.end()) return std::nullopt;
  if (it->second.size() > 1) throw UsageError("option " + name + " given more than once");
  return it->second.front();
}

std::vector<std::string> Args::all(const std::string& name) {
  used_.insert(name);
  const auto it = values_.find(name);
  return it == values_.end() ? std::vector<std::string>{} : it->second;
}

std::string Args::get_or(const std::string& name, const std::string& fallback) { return get(name).value_or(fallback); }

std::string Args::require(const std::string& name) {
  const auto v = get(name);
  if (!v) throw UsageError("option " + name + " is required");
  return *v;
}

double Args::number(const std::string& name, double fallback) {
  const auto v = get(name);
  if (!v) return fallback;
  char* end = nullptr;
  const double x = std::strtod(v->c_str(), &end);
  if (v->empty() || *end != '\0' || !std::isfinite(x))
    throw UsageError("option " + name + " needs a finite number, got '" + *v + "'");
  return x;
}

long Args::integer(const std::string& name, long fallback) {
  const auto v = get(name);
  if (!v) return fallback;
  char* end = nullptr;
  const long x = std::strtol(v->c_str(), &end, 10);
  if (v->empty() || *end != '\0') throw UsageError("option " + name + " needs a whole number, got '" + *v + "'");
  return x;
}

std::vector<std::string> Args::positionals() {
  positionals_used_ = true;
  return positionals_;
}

void Args::finish() const {
  for (const auto& [k, v] : values_)
    if (!used_.count(k)) throw UsageError("unknown option " + k);
  for (const auto& k : flags_set_)
    if (!used_.count(k)) throw UsageError("unknown option " + k);
  if (!positionals_used_ && !positionals_.empty())
    throw UsageError("unexpected argument '" + positionals_.front() + "'");
}

}  // namespace humandyn::cli
