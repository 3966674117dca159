//! `TCP_CONNECT`, `TCP_SEND`, `TCP_RECV`, `TCP_CLOSE` over real sockets, with the argument
//! order of reference §1.8 and timeouts scaled by `time_scale`.

use std::io::{ErrorKind, Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::time::Duration;

use super::parse::Expr;
use super::{As, V};

impl As {
    pub(super) fn tcp(&mut self, op: &str, a: &[Expr]) -> Result<(), String> {
        let want = match op {
            "TCP_CONNECT" | "TCP_SEND" => 4,
            "TCP_RECV" => 6,
            "TCP_CLOSE" => 2,
            other => return Err(format!("{other} is not modelled")),
        };
        // TCP_SEND's timeout (5th) is optional.
        if a.len() != want && !(op == "TCP_SEND" && a.len() == 5) {
            return Err(format!("{op} takes {want} arguments, got {}", a.len()));
        }
        match op {
            "TCP_CONNECT" => {
                let port = self.eval(&a[1])?.num()? as u16;
                let mut ip = [0u8; 4];
                for (k, o) in ip.iter_mut().enumerate() {
                    let r = self.element(&a[2], k)?;
                    *o = self.eval(&Expr::Var(r))?.num()? as u8;
                }
                let tmo = self.eval(&a[3])?.num()? * self.time_scale;
                let addr = SocketAddr::from((ip, port));
                let sock = match TcpStream::connect_timeout(&addr, Duration::from_secs_f64(tmo)) {
                    Ok(s) => {
                        let id = self.next_socket;
                        self.next_socket += 1;
                        self.sockets.insert(id, s);
                        id as f64
                    }
                    Err(_) => -1.0,
                };
                let p = self.arg_place(&a[0])?;
                self.write(&p, V::Num(sock));
            }
            "TCP_SEND" => {
                let sock = self.eval(&a[1])?.num()? as i64;
                let n = self.eval(&a[3])?.num()? as usize;
                let mut bytes = String::new();
                for k in 0..n {
                    let r = self.element(&a[2], k)?;
                    bytes.push_str(self.eval(&Expr::Var(r))?.str()?);
                }
                let ok = match self.sockets.get_mut(&sock) {
                    Some(s) => s.write_all(bytes.as_bytes()).is_ok(),
                    None => false,
                };
                let p = self.arg_place(&a[0])?;
                self.write(&p, V::Num(if ok { 0.0 } else { -1.0 }));
            }
            "TCP_RECV" => {
                let sock = self.eval(&a[1])?.num()? as i64;
                let tmo = self.eval(&a[4])?.num()? * self.time_scale;
                let max = self.eval(&a[5])?.num()? as usize;
                let mut buf = vec![0u8; self.recv_split.max(1)];
                let got = match self.sockets.get_mut(&sock) {
                    Some(s) => {
                        s.set_read_timeout(Some(Duration::from_secs_f64(tmo.max(0.001))))
                            .map_err(|e| format!("socket: {e}"))?;
                        match s.read(&mut buf) {
                            Ok(0) => None,
                            Ok(k) => Some(buf[..k].to_vec()),
                            Err(e)
                                if matches!(
                                    e.kind(),
                                    ErrorKind::WouldBlock | ErrorKind::TimedOut
                                ) =>
                            {
                                None
                            }
                            Err(_) => None,
                        }
                    }
                    None => None,
                };
                let (ret, count) = match got {
                    None => (-1.0, 0.0),
                    Some(bytes) => {
                        let chunks: Vec<&[u8]> = bytes.chunks(max.max(1)).collect();
                        for (k, c) in chunks.iter().enumerate() {
                            let r = self.element(&a[2], k)?;
                            self.set(&r, V::Str(String::from_utf8_lossy(c).into_owned()))?;
                        }
                        (0.0, chunks.len() as f64)
                    }
                };
                let p = self.arg_place(&a[0])?;
                self.write(&p, V::Num(ret));
                let p = self.arg_place(&a[3])?;
                self.write(&p, V::Num(count));
            }
            _ => {
                let sock = self.eval(&a[1])?.num()? as i64;
                let found = self.sockets.remove(&sock).is_some();
                let p = self.arg_place(&a[0])?;
                self.write(&p, V::Num(if found { 0.0 } else { -1.0 }));
            }
        }
        Ok(())
    }
}
