#pragma once
/// Running a library that may crash on hostile input (Assimp: its Debian build asserts and aborts,
/// and its readers dereference what a broken file points at) in a child process, so that the
/// crash becomes an input error instead of ending vantage (issue 15: "no input crashes it").
#include <functional>
#include <string>

namespace vantage::detail {

/// Runs `work` in a forked child and returns the bytes it returned. An InputError thrown there is
/// thrown here with the same words; any other exception there is a std::runtime_error here. A
/// child that dies of a signal throws InputError("<who> crashed on it, so the file is broken
/// (signal N: NAME; it said: LAST LINE)"); one that runs past `cpu_seconds` of CPU time throws
/// InputError("<who> did not finish reading it within N s ..."). A stop request (Ctrl-C, SIGTERM)
/// while waiting kills the child and throws Interrupted. Without fork (it failed), `work` runs in
/// this process.
std::string RunIsolated(const std::function<std::string()>& work,
                        const std::string& who,
                        double cpu_seconds);

}  // namespace vantage::detail
