#pragma once
// Which machine a figure was measured on. Timings leave the project with it (benchmark reports,
// training manifests, the evaluation's tables) because the sessions that produce them do not
// always run on the same CPU, and a wall time without its machine cannot be compared.

#include <string>

namespace deixis {

// The first "model name" of /proc/cpuinfo ("AMD EPYC"), or "unknown CPU" where there is none.
std::string cpu_model();

// "<cpu model>, <n> logical CPUs", the count as std::thread::hardware_concurrency reports it.
std::string machine_description();

}  // namespace deixis
