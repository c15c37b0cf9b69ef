#pragma once
// Reading what `dynamap eval` scores: the truth written by the simulator and by
// `dynamap perturb --add-objects`, and the tables of a `dynamap map` result. Every reader
// checks the file's header against its schema (dynamap/base/csv_schema.h) and every field; an
// error throws InputError naming file:line and the column.

#include <set>
#include <string>
#include <vector>

#include "dynamap/base/pose_track.h"
#include "dynamap/evaluation/evaluation.h"
#include "dynamap/evaluation/session_scores.h"

namespace dynamap {

/// NAME.objects.csv: the truth's bodies per scan.
std::vector<TruthRow> readTruthRows(const std::string& path);
/// NAME.moves.csv: the truth's object moves (t_end not before t_start).
std::vector<TruthMove> readMoves(const std::string& path);
/// A result's tracks.csv.
std::vector<TrackRow> readTracks(const std::string& path);
/// The ids of a result's final object table (objects.csv).
std::set<int> readTableIds(const std::string& path);
/// Drops the rows of objects the final table at `objects_csv` does not hold (withdrawn: a
/// person who stood and walked off) and adds a note saying how many; nothing when the file is
/// missing.
void keepTableRows(const std::string& objects_csv, std::vector<TrackRow>& rows,
                   std::vector<std::string>& notes);
/// A result's final object table (objects.csv): id, size and place of every row.
std::vector<TableRow> readTable(const std::string& path);
/// The simulator's NAME.changes.csv: every change between sessions.
std::vector<ScoredRow> readChangeTruth(const std::string& path);
/// A result's changes.csv (session 0 in every row).
std::vector<ScoredRow> readChangeReport(const std::string& path);
/// perturb --add-objects' NAME.own.csv: the unedited log's object rows.
std::vector<OwnRow> readOwn(const std::string& path);
/// A result's people.csv.
std::vector<PersonTrackRow> readPeople(const std::string& path);
/// `timestamp x y phi` lines (poses.txt, NAME.gt.txt), sorted by time.
std::vector<TimedPose> readPoses(const std::string& path);
/// The raw odometry pose of every scan of a log.
std::vector<TimedPose> odometryPoses(const std::string& log);
/// The truth's file prefix: "rawlogs/arena" (a directory) stands for "rawlogs/arena/arena".
std::string truthPrefix(const std::string& given);

}  // namespace dynamap
