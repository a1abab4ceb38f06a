// python/src/options.hpp -- the keyword arguments search= and threads= as SupermeshOptions,
// checked (ValueError naming the argument).
#pragma once

#include <optional>
#include <string>

#include "arrays.hpp"
#include "tetia/supermesh.hpp"

namespace tetia::python {

inline SupermeshOptions supermesh_options(const std::string& search, std::optional<int> threads) {
  SupermeshOptions options;
  if (search == "front")
    options.search = CandidateSearch::front;
  else if (search == "rtree")
    options.search = CandidateSearch::rtree;
  else
    value_error("tetia: search must be \"front\" or \"rtree\", not \"" + search + "\"");
  if (threads && *threads < 1)
    value_error("tetia: threads must be None (OpenMP's default) or at least 1, not " + std::to_string(*threads));
  options.threads = threads.value_or(0);
  return options;
}

}  // namespace tetia::python
