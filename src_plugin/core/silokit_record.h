/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   GPL-2.0-or-later, like LIGGGHTS, into which it compiles.

   The record files the silokit fixes write (rank 0).
------------------------------------------------------------------------- */

#ifndef SILOKIT_RECORD_H
#define SILOKIT_RECORD_H

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

namespace silokit {

// A record file, closed when the fix that writes it goes (or when it is
// replaced); empty on the ranks that write none.
struct CloseFile {
  void operator()(FILE *file) const { fclose(file); }
};
typedef std::unique_ptr<FILE, CloseFile> RecordFile;

// What a fix restored from a restart file keeps of its record: the data
// lines whose number in column `column` (0-based) is at most `last` (the
// clog index, the time reached when the restart file was written), with a
// relative tolerance for numbers printed with 12-15 digits. Comment lines
// are kept.
struct KeptRows {
  int column;
  double last;
};

// The data lines of `path` past kept.last are those an earlier piece of
// the run wrote after its last restart file (it ran on, then stopped
// without writing another): the restarted run records those steps again,
// so they are removed, and each is recorded once. The file is rewritten
// through a temporary and a rename. Returns the number of lines removed,
// 0 if the file does not exist, -1 if it cannot be rewritten.
inline long drop_rows_past(const std::string &path, const KeptRows &kept)
{
  std::ifstream in(path.c_str());
  if (!in) return 0;
  const double limit = kept.last + 1e-9*std::fabs(kept.last);
  std::vector<std::string> lines;
  long dropped = 0;
  std::string line;
  while (std::getline(in, line)) {
    bool keep = true;
    if (!line.empty() && line[0] != '#') {
      const char *text = line.c_str();
      double value = 0.0;
      bool parsed = true;
      for (int k = 0; k <= kept.column && parsed; ++k) {
        char *end = nullptr;
        value = strtod(text, &end);
        parsed = end != text;        // not: a line cut short by the stop
        text = end;
      }
      keep = parsed && value <= limit;
    }
    if (keep) lines.push_back(line);
    else ++dropped;
  }
  in.close();
  if (dropped == 0) return 0;
  const std::string part = path + ".part";
  FILE *out = fopen(part.c_str(), "w");
  if (!out) return -1;
  for (size_t k = 0; k < lines.size(); ++k) fprintf(out, "%s\n", lines[k].c_str());
  if (fclose(out) != 0 || rename(part.c_str(), path.c_str()) != 0) return -1;
  return dropped;
}

// Opens the record file at `path`: anew (truncated) for a fresh run, for
// appending when the fix's state was read from a restart file, so that the
// pieces of a restarted run write one series and nothing already recorded
// is lost; lines past what the restart file covers are removed first
// (drop_rows_past; their count in *dropped). `header` (its lines without
// the last newline) is written only to an empty file. Empty if the file
// cannot be opened or rewritten.
inline RecordFile open_record(const std::string &path, bool restored, const char *header,
                              const KeptRows &kept, long *dropped)
{
  *dropped = restored ? drop_rows_past(path, kept) : 0;
  if (*dropped < 0) return RecordFile();
  RecordFile file(fopen(path.c_str(), restored ? "a" : "w"));
  if (!file) return file;
  fseek(file.get(), 0, SEEK_END);
  if (ftell(file.get()) == 0) {
    fprintf(file.get(), "%s\n", header);
    fflush(file.get());
  }
  return file;
}

}  // namespace silokit

#endif
