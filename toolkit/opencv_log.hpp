#pragma once
// The tools report every failure themselves, in one line naming the file or option. OpenCV logs
// some of the same failures first, in its own words and naming what the tool did not ask for
// (e.g. "[ERROR:0@0.035] ... Can't open file: '/out/.o.tmp123-0.yml' in write mode" before
// "mdbrief: /out/o.yml: cannot create the output file").
namespace mdbrief {

// Silences OpenCV's log for the rest of the process, unless OPENCV_LOG_LEVEL is set (then
// OpenCV's own setting holds, for debugging). For the tools' entry points only: a library (the
// Python module) must not change the log level of its host, which shares OpenCV with it.
void silenceOpenCvLogUnlessAsked();

}  // namespace mdbrief
