//! The ROS master: an address given by the user, or a `rosmaster` started for the run.

use std::net::{TcpListener, TcpStream, ToSocketAddrs};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// Errors about the ROS master.
#[derive(Debug, thiserror::Error)]
pub enum MasterError {
    /// `rosmaster` could not be started.
    #[error("cannot start rosmaster ({0}); install Debian's python3-rosmaster or pass --ros-master URI")]
    Spawn(std::io::Error),
    /// The master did not answer in time.
    #[error("the ROS master at {uri} did not answer within {secs} s")]
    Timeout {
        /// Its URI.
        uri: String,
        /// How long we waited (s).
        secs: f64,
    },
    /// A URI that is not `http://host:port[/]`.
    #[error("bad ROS master URI '{0}': expected http://HOST:PORT")]
    BadUri(String),
}

/// A master the run talks to; one started here is killed on drop.
#[derive(Debug)]
pub struct Master {
    /// `http://host:port/`.
    pub uri: String,
    child: Option<Child>,
}

/// `host:port` of an `http://host:port[/]` URI.
pub fn host_port(uri: &str) -> Result<String, MasterError> {
    let rest = uri.strip_prefix("http://").ok_or_else(|| MasterError::BadUri(uri.into()))?;
    let hp = rest.trim_end_matches('/');
    match hp.rsplit_once(':') {
        Some((h, p)) if !h.is_empty() && p.parse::<u16>().is_ok() => Ok(hp.to_string()),
        _ => Err(MasterError::BadUri(uri.into())),
    }
}

/// Whether something accepts TCP connections at `host:port`.
pub fn answers(host_port: &str) -> bool {
    host_port
        .to_socket_addrs()
        .ok()
        .and_then(|mut a| a.next())
        .is_some_and(|a| TcpStream::connect_timeout(&a, Duration::from_millis(200)).is_ok())
}

impl Master {
    /// Uses the master at `uri`, failing clearly if nothing answers there.
    pub fn connect(uri: &str) -> Result<Master, MasterError> {
        let hp = host_port(uri)?;
        if !answers(&hp) {
            return Err(MasterError::Timeout { uri: uri.into(), secs: 0.2 });
        }
        Ok(Master { uri: format!("http://{hp}/"), child: None })
    }

    /// Starts `rosmaster --core` on a free loopback port and waits (up to 10 s) until it answers.
    pub fn start() -> Result<Master, MasterError> {
        let port = TcpListener::bind("127.0.0.1:0").and_then(|l| l.local_addr()).map_err(MasterError::Spawn)?.port();
        let child = Command::new("rosmaster")
            .args(["--core", "-p", &port.to_string()])
            .env("ROS_IP", "127.0.0.1")
            .env("ROS_MASTER_URI", format!("http://127.0.0.1:{port}/"))
            .env("ROS_LOG_DIR", std::env::temp_dir().join("xhab_ros_log"))
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .map_err(MasterError::Spawn)?;
        let mut m = Master { uri: format!("http://127.0.0.1:{port}/"), child: Some(child) };
        let t0 = Instant::now();
        let hp = format!("127.0.0.1:{port}");
        while t0.elapsed() < Duration::from_secs(10) {
            if answers(&hp) {
                tracing::info!("started rosmaster at {}", m.uri);
                return Ok(m);
            }
            if let Some(Ok(Some(status))) = m.child.as_mut().map(|c| c.try_wait()) {
                return Err(MasterError::Spawn(std::io::Error::other(format!("rosmaster exited with {status}"))));
            }
            std::thread::sleep(Duration::from_millis(50));
        }
        Err(MasterError::Timeout { uri: m.uri.clone(), secs: 10.0 })
    }

    /// The master at `uri` if given, else a new one.
    pub fn connect_or_start(uri: Option<&str>) -> Result<Master, MasterError> {
        match uri {
            Some(u) => Master::connect(u),
            None => Master::start(),
        }
    }

    /// Sets the boolean parameter `name` (e.g. `/use_sim_time`) on the master, by XML-RPC's
    /// `setParam`, as `rosparam set` does.
    pub fn set_param_bool(&self, name: &str, value: bool) -> Result<(), MasterError> {
        use std::io::{Read, Write};
        let hp = host_port(&self.uri)?;
        let body = format!(
            "<?xml version=\"1.0\"?><methodCall><methodName>setParam</methodName><params><param><value><string>/xhab</string></value></param><param><value><string>{name}</string></value></param><param><value><boolean>{}</boolean></value></param></params></methodCall>",
            value as u8
        );
        let req = format!("POST / HTTP/1.1\r\nHost: {hp}\r\nContent-Type: text/xml\r\nContent-Length: {}\r\nConnection: close\r\n\r\n{body}", body.len());
        let addr = hp.to_socket_addrs().ok().and_then(|mut a| a.next()).ok_or_else(|| MasterError::BadUri(self.uri.clone()))?;
        let timeout = || MasterError::Timeout { uri: self.uri.clone(), secs: 5.0 };
        let mut s = TcpStream::connect_timeout(&addr, Duration::from_secs(5)).map_err(|_| timeout())?;
        s.set_read_timeout(Some(Duration::from_secs(5))).map_err(MasterError::Spawn)?;
        s.write_all(req.as_bytes()).map_err(|_| timeout())?;
        let mut reply = String::new();
        let _ = s.read_to_string(&mut reply);
        // The master answers [code, status message, ignore]; code 1 is success.
        if reply.contains("<int>1</int>") || reply.contains("<i4>1</i4>") {
            Ok(())
        } else {
            Err(MasterError::Spawn(std::io::Error::other(format!("setParam {name}: the master at {} answered: {}", self.uri, reply.lines().last().unwrap_or("")))))
        }
    }

    /// Whether this master was started by us.
    pub fn owned(&self) -> bool {
        self.child.is_some()
    }
}

impl Drop for Master {
    fn drop(&mut self) {
        if let Some(c) = self.child.as_mut() {
            let _ = c.kill();
            let _ = c.wait();
        }
    }
}
