#include "warnings.h"

#include "absl/strings/str_cat.h"

namespace tessera::render {

void WarningList::Add(const std::string& kind, const std::string& message) {
  auto [it, inserted] = index_of_kind_.emplace(kind, entries_.size());
  if (inserted) {
    entries_.push_back({message, 0});
  } else {
    ++entries_[it->second].more;
  }
}

std::vector<std::string> WarningList::Lines() const {
  std::vector<std::string> lines;
  for (const Entry& entry : entries_) {
    std::string line = absl::StrCat(file_, ": ", entry.message);
    if (entry.more > 0) absl::StrAppend(&line, " (and ", entry.more, " more like it)");
    lines.push_back(std::move(line));
  }
  return lines;
}

}  // namespace tessera::render
