//! The fake Mech-Mind vision server (`krlkit sim serve`): a loopback test double that speaks
//! the Standard Interface protocol (ASCII or HEX framing; the 1.x or 2.x interface) and
//! answers from a TOML scenario.
//!
//! ```no_run
//! use krlkit::sim::{Scenario, Server};
//! let server = Server::start(Scenario::default_embedded(), "127.0.0.1:0")?;
//! println!("listening on {}", server.addr());
//! // ... connect a client, send "901\r", read "901,1101\r" ...
//! for r in server.requests() { println!("{r}"); }
//! server.shutdown();
//! # Ok::<(), std::io::Error>(())
//! ```
//!
//! Modules: [`scenario`] (the TOML format, checked with located errors; see `SCENARIO.md`),
//! [`protocol`] (the [`protocol::Codec`] that frames, decodes and encodes; the ASCII format,
//! lenient decoding, typed replies), [`hex`] (the HEX format: 4-byte int32/float32 fields,
//! zero padding), [`state`] (the per-command state machine, per interface version), [`server`] (TCP sessions,
//! faults, request log), [`clock`] (the time Notify
//! messages expire on: wall time, or a manual clock in tests).
//!
//! Wire handling (ASCII): a message ends at CR (LF is accepted as a terminator too, so `\r\n` yields
//! one message plus an ignored empty one), or, without a terminator, once no byte came for
//! `ascii_unterminated_ms` (50 ms; Mech-Mind's 1.x clients send `cmd,...,` without CR and the
//! vendor's server takes what one read delivers); fields are split on `,` and trimmed of spaces and
//! tabs; one trailing `,` is allowed; numbers may be `1`, `1.0`, `-0`, `1.5E3`; integer fields must be integral. Empty
//! messages are ignored. Replies end in CR. HEX (`codec = "hex-le"`/`"hex-be"`): see [`hex`];
//! requests of 64 or 660 bytes, replies padded to the KUKA frame (660 bytes). Several commands per connection and a connection
//! per command both work; state persists across connections.
//!
//! Clients are served concurrently, each connection in its own session (input buffer, idle
//! timer, connection number) on its own thread, all sharing one protocol state: a real
//! Mech-Vision runs one project state that every robot connection addresses (the KUKA package
//! triggers on one connection and fetches on the next), and serves several robots at once (up
//! to four ports [S]); how it treats a second client on one port is not documented [U], so the
//! test double does the useful thing and serves it. At most `max_clients` sessions (default
//! 256) are open at once; a further connection is refused: closed at once, with a
//! "connection refused" entry in the request log. A session is closed when no complete message
//! arrived for `idle_timeout_ms` (blank lines and loose bytes do not count). A message longer
//! than `max_message_bytes` gets `0,3002` and the connection is closed, so memory stays
//! bounded (per session and by the session cap).
//!
//! Choices the reference leaves open ([U]), made here:
//! - Error replies are `<cmd>,<status>` (no further fields); an unreadable command field
//!   answers `0,3002`; a wrong field count or a non-integral integer field answers `<cmd>,3002`.
//! - 101 checks the payload length for its pose type (0, 2, 3: six values; 1: twelve); an
//!   invalid pose type answers 1026 whatever follows; a negative expected count 1018.
//! - 102 and 110 share the point cursor of the last 101; 105 has its own path cursor (the
//!   expected count of 101 limits points, not path waypoints). A call
//!   after everything was sent answers "no result" (1002; 2022 for Viz) instead of repeating.
//! - 105/205 "first Vision Move position" counts from the first waypoint of the current batch
//!   (1-based); 0 when no Vision Move waypoint remains. An invalid pose kind answers 1026 (105)
//!   or 2012 (205, 210); a waypoint without the requested kind answers 1016 (105) or 2022.
//! - 205 and 210 share one path cursor, reset by 201; before 201 they answer 2022.
//! - 210 formats 1/3 return joints, 2/4 TCP; Vision Move data (20 values) only for formats
//!   3/4 on Vision Move waypoints; custom values (count, then values) only on Vision Move
//!   waypoints, other waypoints end with count 0.
//! - 206 takes no argument in 1.x and the number of gripper sections in 2.x (the list does not
//!   depend on it); it answers 2011 before 201 or without a DO list.
//! - 106 takes the project ID only in 1.x (project and gripper sections in 2.x); it answers 1020 before that
//!   project's 101 and 1008 when the project has no DO list.
//! - 111 (project, pose kind) returns one waypoint of the project's path per call and shares
//!   105's cursor; its Vision Move data always has the 21-value layout (1.8.3/2.x) and
//!   comes on Vision Move waypoints only, whatever the pose kind; no custom values; the 1.x
//!   (seed 001) layout has the speed after the tool, the 2.x one does not. 210 uses
//!   the layout of `[server] vision_move_layout` (default: KUKA 1.x, 20 values, in 1.x; 21 in 2.x). Data
//!   given in the other layout is converted field by field (the catalog's
//!   `[[vision_move_field]]`); fields the given layout lacks are 0.
//! - 207/208 look up `read` and `write` lines of the scenario's `property_config`
//!   separately (3008 when the Config ID has no line of that kind, 2014 without `[viz]`); a
//!   208 applies all write lines of its ID, and a later 207 of the same step parameter reads
//!   the written value. They work with or without a started Mech-Viz project.
//! - 601: 101 and 201 put the messages of the project's Notify steps into one buffer (at
//!   start + `after_ms`); each 601 returns and removes the oldest message that is due; a
//!   message not read within [`state::NOTIFY_LIFETIME`] (the reference's 3 s buffer time) of
//!   becoming due is dropped, on the server's clock. With nothing waiting the reply is `601,0`, as the reply has no
//!   status field [U]; a malformed 601 still answers `601,3002`. At most
//!   [`state::NOTIFY_CAPACITY`] messages are kept (the earliest go first).
//! - 203/204 need a `[viz]` section (2014 otherwise) but not a started project.
//! - 701: state 0 restarts the script; states 1 and 2 (reached / failed to reach) both advance;
//!   after the last point the reply has done = 1 and zeros; 1 or 2 before any 0 answers 7001.
//! - Faults: `status`, `garbage` and `drop` answer without touching the state; `wrong_echo`
//!   and a bare `delay_ms` answer normally (the state advances).
//! - Interface 2.x (`interface = "2.x"`): the 8th field of 102/105/205 points is the tool ID
//!   (`tool`, default 0), 901 answers `901,9100,1,<1 with a [viz]>,1`, 202 stops Mech-Viz
//!   (2104), 502 answers 3001. In 1.x, 202 answers 3001 (the KUKA 1.x interface has no
//!   wrapper and the 1.x success code is unsettled: 2101 or 2104). The 2.x-only commands 100,
//!   104, 200, 503-507 answer 3001 in both because the catalog does not list them.
//! - HEX: the speed of a point or waypoint travels as an int32 (rounded); custom values,
//!   Vision Move data and step parameter values as float32 [U, catalog `[hex]`]. A garbage
//!   reply is the echo field followed by the garbage text's bytes, padded.

pub mod clock;
pub mod hex;
pub mod protocol;
pub mod scenario;
pub mod server;
pub mod state;

pub use clock::{Clock, ManualClock, SystemClock};
pub use scenario::{Dialect, Scenario, ScenarioError};
pub use server::{Observer, RequestLog, Server};
