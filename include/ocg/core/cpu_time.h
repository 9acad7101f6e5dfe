#pragma once
// CPU time, the measure that stays comparable when other processes share the cores: wall
// time includes the time a thread waited for a core, CPU time only the time it ran.

namespace ocg {

// CPU seconds the calling thread has used since it started.
double ThreadCpuSeconds();

// CPU seconds (user + system) every thread of this process has used, the joined ones
// included.
double ProcessCpuSeconds();

}  // namespace ocg
