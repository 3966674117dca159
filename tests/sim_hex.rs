//! `sim serve` in HEX mode, driven by a small independent client written from the published
//! layouts only (protocol reference 1.2 and issue 14), not from krlkit's codec: every field is
//! 4 bytes, command/status/counts/label/speed int32, pose values IEEE-754 float32; KUKA sends
//! 660-byte frames, other brands 64-byte requests; a 102 reply is
//! `[cmd][status][allSent][count][visPos]` then `count x (6 float32, int32 label, int32 speed)`.
//! Also the ASCII requests of Mech-Mind's 1.x clients (`cmd,...,` without CR).

mod sim_support;

use std::io::{ErrorKind, Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::time::{Duration, Instant};

use sim_support::{fixture, scenario, start};

#[derive(Clone, Copy)]
enum W {
    I(i32),
    F(f32),
}

#[derive(Clone, Copy, PartialEq)]
enum Order {
    Le,
    Be,
}

fn pack(fields: &[W], size: usize, order: Order) -> Vec<u8> {
    let mut out = Vec::new();
    for f in fields {
        let mut b = match f {
            W::I(v) => v.to_le_bytes(),
            W::F(v) => v.to_le_bytes(),
        };
        if order == Order::Be {
            b.reverse();
        }
        out.extend_from_slice(&b);
    }
    out.resize(size.max(out.len()), 0);
    out
}

fn word(bytes: &[u8], i: usize, order: Order) -> [u8; 4] {
    let mut w = [0u8; 4];
    w.copy_from_slice(&bytes[4 * i..4 * i + 4]);
    if order == Order::Be {
        w.reverse();
    }
    w
}

fn int(bytes: &[u8], i: usize, order: Order) -> i32 {
    i32::from_le_bytes(word(bytes, i, order))
}

fn real(bytes: &[u8], i: usize, order: Order) -> f32 {
    f32::from_le_bytes(word(bytes, i, order))
}

struct HexClient {
    stream: TcpStream,
}

impl HexClient {
    fn connect(addr: SocketAddr) -> HexClient {
        let stream = TcpStream::connect_timeout(&addr, Duration::from_secs(3)).unwrap();
        stream
            .set_read_timeout(Some(Duration::from_secs(3)))
            .unwrap();
        HexClient { stream }
    }

    /// Send a request and read a reply of exactly `reply` bytes.
    fn ask(&mut self, request: &[u8], reply: usize) -> Vec<u8> {
        self.stream.write_all(request).unwrap();
        let mut buf = vec![0u8; reply];
        self.stream
            .read_exact(&mut buf)
            .expect("a whole reply frame");
        buf
    }

    /// Bytes that arrive within `wait` (none: the server answered nothing).
    fn pending(&mut self, wait: Duration) -> Vec<u8> {
        self.stream.set_read_timeout(Some(wait)).unwrap();
        let mut got = Vec::new();
        let mut chunk = [0u8; 2048];
        loop {
            match self.stream.read(&mut chunk) {
                Ok(0) => break,
                Ok(n) => got.extend_from_slice(&chunk[..n]),
                Err(e) if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) => {
                    break;
                }
                Err(_) => break,
            }
        }
        got
    }
}

fn hex_scenario(name: &str, extra: &str) -> krlkit::sim::Scenario {
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/fixtures/scenarios")
            .join(name),
    )
    .unwrap()
    .replace("[server]\n", &format!("[server]\n{extra}\n"));
    scenario(&text)
}

#[test]
fn kuka_frames_of_660_bytes_fetch_every_point() {
    let sc = hex_scenario("vision_pick.toml", "codec = \"hex-le\"");
    let points = sc.projects[0].points.clone();
    let server = start(sc);
    let mut c = HexClient::connect(server.addr());
    let le = Order::Le;
    let mut start = vec![W::I(101), W::I(3), W::I(0), W::I(0)];
    start.extend([W::F(0.0); 6]);
    let r = c.ask(&pack(&start, 660, le), 660);
    assert_eq!((int(&r, 0, le), int(&r, 1, le)), (101, 1102));
    assert!(r[8..].iter().all(|b| *b == 0), "padded with zeros");
    let mut got = Vec::new();
    loop {
        let r = c.ask(&pack(&[W::I(102), W::I(3)], 660, le), 660);
        assert_eq!((int(&r, 0, le), int(&r, 1, le)), (102, 1100));
        let (all_sent, count) = (int(&r, 2, le), int(&r, 3, le));
        assert!(count <= 20);
        let end = 20 + 32 * count as usize;
        assert!(r[end..].iter().all(|b| *b == 0), "nothing after the points");
        for i in 0..count as usize {
            let base = 5 + 8 * i;
            let pose: Vec<f32> = (0..6).map(|k| real(&r, base + k, le)).collect();
            got.push((pose, int(&r, base + 6, le), int(&r, base + 7, le)));
        }
        if all_sent == 1 {
            break;
        }
    }
    assert_eq!(got.len(), points.len(), "20 + 5");
    for (p, (pose, label, speed)) in points.iter().zip(&got) {
        let want: Vec<f32> = p.pose.iter().map(|v| *v as f32).collect();
        assert_eq!(&want, pose);
        assert_eq!(i64::from(*label), p.label);
        assert_eq!(f64::from(*speed), p.speed.round());
    }
    let log = server.requests();
    assert_eq!(log[1].raw, "102,3");
    assert!(log.iter().all(|r| r.note.is_none()), "{log:?}");
}

#[test]
fn other_brands_send_64_bytes_big_endian_and_get_unpadded_replies() {
    let sc = hex_scenario(
        "vision_pick.toml",
        "codec = \"hex-be\"\nhex_reply_bytes = 0",
    );
    let server = start(sc);
    let mut c = HexClient::connect(server.addr());
    let be = Order::Be;
    // As the reference's example (`103,1,2` big-endian is 00 00 00 67 | 00 00 00 01 | ...),
    // for project 3.
    let req = pack(&[W::I(103), W::I(3), W::I(2)], 64, be);
    assert_eq!(&req[..12], [0, 0, 0, 0x67, 0, 0, 0, 3, 0, 0, 0, 2]);
    let r = c.ask(&req, 8);
    assert_eq!((int(&r, 0, be), int(&r, 1, be)), (103, 1107));
    // 501 with float32 dimensions.
    let req = pack(
        &[W::I(501), W::I(3), W::F(500.0), W::F(300.5), W::F(200.0)],
        64,
        be,
    );
    let r = c.ask(&req, 8);
    assert_eq!((int(&r, 0, be), int(&r, 1, be)), (501, 1108));
    assert_eq!(server.requests()[1].args, [3.0, 500.0, 300.5, 200.0]);
    assert!(c.pending(Duration::from_millis(100)).is_empty());
}

#[test]
fn the_2x_interface_answers_9100_with_its_flags() {
    let sc = hex_scenario("viz_path.toml", "codec = \"hex-le\"")
        .with_interface(krlkit::catalog::Interface::V2)
        .unwrap();
    let server = start(sc);
    let mut c = HexClient::connect(server.addr());
    let le = Order::Le;
    let r = c.ask(&pack(&[W::I(901)], 660, le), 660);
    let got: Vec<i32> = (0..5).map(|i| int(&r, i, le)).collect();
    assert_eq!(got, [901, 9100, 1, 1, 1]);
    let r = c.ask(&pack(&[W::I(202)], 660, le), 660);
    assert_eq!((int(&r, 0, le), int(&r, 1, le)), (202, 2104));
    // 502 does not exist in 2.x.
    let mut ext = vec![W::I(502)];
    ext.extend([W::F(1.0); 6]);
    let r = c.ask(&pack(&ext, 660, le), 660);
    assert_eq!((int(&r, 0, le), int(&r, 1, le)), (502, 3001));
}

#[test]
fn malformed_frames_get_the_documented_errors() {
    let sc = hex_scenario(
        "vision_pick.toml",
        "codec = \"hex-le\"\nidle_timeout_ms = 500",
    );
    let server = start(sc);
    let le = Order::Le;
    let mut c = HexClient::connect(server.addr());
    // Unknown command: 3001; a float field that is not a number: 3002; a command field that
    // is not a positive number: 0,3002.
    let r = c.ask(&pack(&[W::I(999), W::I(1)], 660, le), 660);
    assert_eq!((int(&r, 0, le), int(&r, 1, le)), (999, 3001));
    let nan = [W::I(501), W::I(3), W::F(f32::NAN), W::F(1.0), W::F(1.0)];
    let r = c.ask(&pack(&nan, 660, le), 660);
    assert_eq!((int(&r, 0, le), int(&r, 1, le)), (501, 3002));
    let r = c.ask(&pack(&[W::I(-7)], 64, le), 660);
    assert_eq!((int(&r, 0, le), int(&r, 1, le)), (0, 3002));
    // Megabytes of zero padding are skipped without growing the server's memory; the next
    // request is answered.
    let zeros = vec![0u8; 1 << 20];
    c.stream.write_all(&zeros).unwrap();
    let r = c.ask(&pack(&[W::I(901)], 64, le), 660);
    assert_eq!((int(&r, 0, le), int(&r, 1, le)), (901, 1101));
    // A request shorter than 64 bytes is never answered; the idle timeout closes it.
    let t = Instant::now();
    let mut short = HexClient::connect(server.addr());
    short.stream.write_all(&pack(&[W::I(901)], 8, le)).unwrap();
    short
        .stream
        .set_read_timeout(Some(Duration::from_secs(3)))
        .unwrap();
    let mut buf = [0u8; 16];
    assert_eq!(
        short.stream.read(&mut buf).unwrap_or(0),
        0,
        "closed unanswered"
    );
    assert!(t.elapsed() >= Duration::from_millis(400));
    let log = server.requests();
    assert_eq!(log.len(), 4, "{log:?}");
    assert!(
        log[1]
            .note
            .as_deref()
            .unwrap_or("")
            .contains("4-byte fields")
    );
}

#[test]
fn ascii_requests_of_1x_clients_end_without_cr() {
    let server = start(fixture("vision_pick.toml"));
    let mut c = HexClient::connect(server.addr());
    // `cmd,...,` with a trailing comma and no CR, one write each.
    c.stream.write_all(b"103,3,2,").unwrap();
    let r = c.pending(Duration::from_millis(400));
    assert_eq!(r, b"103,1107\r");
    c.stream.write_all(b"901").unwrap();
    assert_eq!(c.pending(Duration::from_millis(400)), b"901,1101\r");
    // With CR it is answered at once, as before.
    c.stream.write_all(b"901,\r").unwrap();
    assert_eq!(c.pending(Duration::from_millis(100)), b"901,1101\r");
}
