#pragma once
// The header line of each CSV table dynamap writes or reads: one schema shared by the writers
// (the simulator, perturb, a map result's tables) and the readers (eval), so a column added on
// one side cannot be missed on the other. Written without the trailing newline.

namespace dynamap::csv {

/// The truth's bodies per scan: NAME.objects.csv of the simulator and of perturb.
inline constexpr const char* kTruthRows = "scan_index,t,kind,id,x,y,diameter,hits";
/// The truth's object moves: NAME.moves.csv.
inline constexpr const char* kMoves = "move_id,object_id,t_start,t_end,from_x,from_y,to_x,to_y";
/// The truth of a multi-session scenario: NAME.changes.csv, every change between sessions
/// (id: the object's or the wall's number; a wall's from and to are its ends).
inline constexpr const char* kSessionChanges = "session,kind,id,size_m,from_x,from_y,to_x,to_y";
/// perturb --add-objects' NAME.own.csv: the unedited log's own object rows.
inline constexpr const char* kOwn = "scan_index,cx,cy";
/// A map result's tracks.csv: every object report of every scan.
inline constexpr const char* kTracks =
    "scan_index,t,object_id,cx,cy,size_m,x_min,x_max,y_min,y_max";
/// A map result's objects.csv: the final object table.
inline constexpr const char* kObjects =
    "id,label,size_m,cx,cy,x_min,x_max,y_min,y_max,state,first_seen_t,last_seen_t,n_moves";
/// A map result's changes.csv (with --prior): what changed since the prior session.
inline constexpr const char* kChanges =
    "kind,id,size_m,from_x,from_y,to_x,to_y,first_seen_t,cells";
/// A map result's people.csv: every person track of every scan.
inline constexpr const char* kPeople = "scan_index,t,person_id,x,y,vx,vy";

}  // namespace dynamap::csv
