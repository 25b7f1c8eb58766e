// A command's report folder as a transaction: every file is written into a
// temporary folder beside it (`.NAME.partial-PID`), which replaces DIR in one
// rename at Commit(). Until then an earlier report in DIR stays as it was; a
// run that throws leaves nothing (the temporary folder is removed); a run that
// stops early writes a report that says so, commits it and exits non-zero. So
// DIR never holds files of two runs. An existing, non-empty DIR is refused
// unless `overwrite`, and even then unless it holds a report of the command
// (its `signature` file): --overwrite never deletes a folder of other files.
#pragma once

#include <string>

namespace aerograsp {

class ReportFolder {
 public:
  /// `signature`: the file every report of the command holds (summary.json,
  /// sequence.yaml, labels.csv, ...).
  /// @throws ConfigError "DIR: holds an earlier report; --overwrite replaces it"
  /// when DIR holds a report and `overwrite` is false; "DIR: is not empty and
  /// holds no report (no SIGNATURE); choose another folder" when DIR holds other
  /// files; "DIR: is a file, not a report folder" when DIR is a file;
  /// std::runtime_error when the temporary folder cannot be made.
  ReportFolder(const std::string& dir, bool overwrite,
               const std::string& signature = "summary.json");
  /// Removes the temporary folder unless committed.
  ~ReportFolder();
  ReportFolder(const ReportFolder&) = delete;
  ReportFolder& operator=(const ReportFolder&) = delete;

  /// Where to write now (the temporary folder).
  const std::string& path() const { return work_; }
  /// Where the report will be, as the user gave it.
  const std::string& final_path() const { return shown_; }
  /// A path under path(), or a message naming such paths anywhere in it, as it
  /// will read after the commit, for what the command prints.
  std::string Final(const std::string& written) const;
  /// Moves the report into place (replacing an earlier one); returns final_path().
  /// @throws std::runtime_error naming DIR when it cannot.
  const std::string& Commit();

 private:
  std::string dir_, shown_, work_;
  bool committed_ = false;
};

}  // namespace aerograsp
