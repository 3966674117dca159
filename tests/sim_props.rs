//! Invariants: no input crashes the server or the state machine; replies are one line that
//! echoes the command; lenient number spellings decode to the same value.

mod sim_support;

use krlkit::sim::Scenario;
use krlkit::sim::protocol::{DecodeError, decode};
use krlkit::sim::state::{NOTIFY_CAPACITY, State};
use proptest::prelude::*;
use sim_support::{Client, Read1, fixture, start};

fn message() -> impl Strategy<Value = String> {
    let field = prop_oneof![
        Just("101".to_string()),
        Just("102".to_string()),
        Just("205".to_string()),
        Just("210".to_string()),
        Just("701".to_string()),
        Just("106".to_string()),
        Just("111".to_string()),
        Just("207".to_string()),
        Just("208".to_string()),
        Just("601".to_string()),
        (-5i64..1000).prop_map(|v| v.to_string()),
        any::<f64>().prop_map(|v| v.to_string()),
        "[ 0-9eE.+-]{0,6}",
        ".{0,4}",
    ];
    proptest::collection::vec(field, 1..16).prop_map(|f| f.join(","))
}

proptest! {
    #[test]
    fn state_machine_answers_everything_with_one_echoing_line(msgs in proptest::collection::vec(message(), 1..20)) {
        let mut state = State::new(Scenario::default_embedded());
        for m in msgs {
            let reply = match decode(&m) {
                Ok(req) => {
                    let r = state.handle(&req).text();
                    let echo = req.command.to_string();
                    prop_assert!(r.starts_with(&format!("{echo},")), "{m:?} -> {r:?}");
                    r
                }
                Err(DecodeError::NoCommand) => "0,3002".to_string(),
                Err(DecodeError::BadField(c)) => format!("{c},3002"),
            };
            prop_assert!(reply.is_ascii() && !reply.contains(['\r', '\n']));
            prop_assert!(state.notices.len() <= NOTIFY_CAPACITY);
        }
    }

    #[test]
    fn number_spellings_decode_alike(v in -100_000i64..100_000, frac in 0u32..10_000) {
        let x = v as f64 + f64::from(frac) / 10_000.0;
        let spellings = [format!("{x}"), format!(" {x} "), format!("{x:e}"), format!("{x:E}"), format!("{x:.6}")];
        for s in spellings {
            let r = decode(&format!("901,{s}")).map_err(|e| TestCaseError::fail(format!("{s}: {e:?}")))?;
            prop_assert!((r.args[0] - x).abs() < 1e-6, "{s}");
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(12))]
    #[test]
    fn random_bytes_never_break_the_server(blobs in proptest::collection::vec(proptest::collection::vec(any::<u8>(), 0..600), 1..6)) {
        let server = start(fixture("viz_path.toml"));
        for blob in &blobs {
            let mut c = Client::connect(server.addr());
            c.send_raw(blob);
            c.send_raw(b"\r");
            // Read whatever comes back until the server has answered everything.
            c.set_read_timeout(std::time::Duration::from_millis(50));
            while let Read1::Line(_) = c.read() {}
        }
        prop_assert_eq!(sim_support::ask_once(server.addr(), "901"), "901,1101");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]
    #[test]
    fn scenario_loading_never_panics(text in "(\\[\\[?(project|viz|fault|server|calibration)(\\.point|\\.waypoint|\\.path|\\.notify|\\.property)?\\]\\]?\n|[a-z_]{1,12} = (-?[0-9]{1,4}|\\[[0-9, .]{0,20}\\]|\"[a-z0-9]{0,5}\"|true|inf|nan)\n){0,12}") {
        if let Err(e) = Scenario::from_toml_str(&text, "p.toml") {
            prop_assert!(e.line >= 1 && e.col >= 1);
            prop_assert!(!e.message.is_empty() && !e.help.is_empty());
        }
    }
}
