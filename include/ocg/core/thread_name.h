#pragma once
// Names the calling thread, so that profilers (perf report --sort comm), debuggers and
// top -H tell tracking, local mapping, loop closing and the OCG apart.

#include <string>

namespace ocg {

// Sets the calling thread's name as the OS shows it. Linux keeps at most 15 characters;
// a longer name is cut. Where naming is not supported it does nothing: a name is an aid,
// never needed for correctness.
void NameThisThread(const std::string& name);

// The calling thread's name as the OS shows it ("" where it cannot be read).
std::string ThisThreadName();

}  // namespace ocg
