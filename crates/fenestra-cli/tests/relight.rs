//! `fenestra relight` as a user meets it: precompute (resumed after an interruption, refused
//! over other settings), render, export to its path-traced ground truth, and the viewer page
//! driven in headless Chromium.

mod common;

use common::{fenestra, tmp};
use fenestra_core::image::Image;
use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

fn ok(o: &Output) -> String {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn s(p: &Path) -> &str {
    p.to_str().expect("utf-8")
}

/// A three-frame animation of the relight room, precomputed small into `dir` (`extra`
/// arguments added).
fn precompute(dir: &Path, extra: &[&str]) -> Output {
    let animation = dir.with_extension("json");
    std::fs::write(
        &animation,
        r#"{ "frames": 3, "objects": { "crate": [ { "frame": 0 }, { "frame": 2, "translate": [1, 0, 0] } ] } }"#,
    )
    .expect("animation");
    let mut args = vec![
        "relight",
        "precompute",
        "builtin:relight-room",
        "--animation",
        s(&animation),
        "-o",
        s(dir),
        "--resolution",
        "32x24",
        "--gather",
        "512",
        "--clusters",
        "8",
        "--keep",
        "128",
        "--explored",
        "0.5",
        "--schedule",
        "0:2,4:2",
    ];
    args.extend_from_slice(extra);
    fenestra(&args)
}

fn mean(path: &Path) -> f64 {
    let image = Image::read(path).expect("image");
    image
        .pixels
        .iter()
        .map(|p| p.luminance() as f64)
        .sum::<f64>()
        / image.pixels.len() as f64
}

#[test]
fn precompute_resumes_render_relights_and_export_gives_the_ground_truth() {
    let dir = tmp("seq");
    ok(&precompute(&dir, &["--quiet"]));
    for f in [
        "relight.json",
        "animation.json",
        "lights.json",
        "frames/0000.rlf",
        "frames/0002.rlf",
    ] {
        assert!(dir.join(f).exists(), "{f} missing");
    }
    // An interrupted precomputation resumes with the frames it lacks.
    std::fs::remove_file(dir.join("frames/0001.rlf")).expect("remove");
    // Not quiet: it says what it resumes.
    let o = precompute(&dir, &[]);
    let err = ok(&o);
    assert!(err.contains("2 of 3 frames already precomputed"), "{err}");
    assert!(dir.join("frames/0001.rlf").exists());
    // Other settings in the same folder are refused, saying which.
    let o = precompute(&dir, &["--seed", "2", "--quiet"]);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("other settings (seed 1 there, 2 now)"),
        "{err}"
    );

    // Relit with the precomputation's lights, against the path-traced frame (direct light
    // and one bounce, through pixel centres).
    let out = tmp("relit");
    ok(&fenestra(&[
        "relight",
        "render",
        s(&dir),
        "-o",
        s(&out),
        "--quiet",
    ]));
    for f in 0..3 {
        assert!(
            out.join(format!("frame-{f:04}.exr")).exists()
                && out.join(format!("frame-{f:04}.png")).exists()
        );
    }
    let pbrt = tmp("truth.pbrt");
    ok(&fenestra(&[
        "relight",
        "export",
        s(&dir),
        "--frame",
        "1",
        "-o",
        s(&pbrt),
    ]));
    let truth = tmp("truth.exr");
    ok(&fenestra(&[
        "render",
        s(&pbrt),
        "--max-depth",
        "3",
        "--spp",
        "256",
        "--quiet",
        "-o",
        s(&truth),
    ]));
    let (relit, traced) = (mean(&out.join("frame-0001.exr")), mean(&truth));
    assert!(
        (relit - traced).abs() < 0.05 * traced,
        "image means: relit {relit}, path traced {traced}"
    );

    // Light is linear: every light twice as bright, the frame twice as bright.
    let lights = std::fs::read_to_string(dir.join("lights.json")).expect("lights");
    let mut doubled: serde_json::Value = serde_json::from_str(&lights).expect("json");
    for l in doubled["lights"].as_array_mut().expect("lights") {
        for c in l["intensity"].as_array_mut().expect("intensity") {
            *c = serde_json::json!(c.as_f64().expect("number") * 2.0);
        }
    }
    let doubled_path = tmp("doubled.json");
    std::fs::write(&doubled_path, doubled.to_string()).expect("write");
    let out2 = tmp("relit2");
    ok(&fenestra(&[
        "relight",
        "render",
        s(&dir),
        "--lights",
        s(&doubled_path),
        "--frames",
        "1..2",
        "-o",
        s(&out2),
        "--quiet",
    ]));
    let (a, b) = (
        Image::read(&out.join("frame-0001.exr")).expect("a"),
        Image::read(&out2.join("frame-0001.exr")).expect("b"),
    );
    for (p, q) in a.pixels.iter().zip(&b.pixels) {
        assert!(
            (q.luminance() - 2.0 * p.luminance()).abs() <= 1e-4 * (1.0 + q.luminance()),
            "{p:?} {q:?}"
        );
    }

    // Clear errors.
    let o = fenestra(&[
        "relight",
        "render",
        s(&dir),
        "--frames",
        "2..5",
        "-o",
        s(&out),
    ]);
    assert!(
        !o.status.success() && String::from_utf8_lossy(&o.stderr).contains("bad --frames '2..5'")
    );
    let o = precompute(&tmp("relight-no-neighbours"), &["--neighbours", "0"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && err.contains("--neighbours must be at least 1"),
        "{err}"
    );
    std::fs::write(
        &doubled_path,
        r#"{ "lights": [ { "type": "point", "position": [0, 0, 0] } ] }"#,
    )
    .expect("write");
    let o = fenestra(&[
        "relight",
        "render",
        s(&dir),
        "--lights",
        s(&doubled_path),
        "-o",
        s(&out),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && err.contains("doubled.json:1:") && err.contains("intensity"),
        "{err}"
    );
    // An export never replaces a file it reads (here a lights file named like a scene).
    let named_pbrt = tmp("lights.pbrt");
    std::fs::copy(dir.join("lights.json"), &named_pbrt).expect("copy");
    let o = fenestra(&[
        "relight",
        "export",
        s(&dir),
        "--frame",
        "1",
        "--lights",
        s(&named_pbrt),
        "-o",
        s(&named_pbrt),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && err.contains("refusing to overwrite it"),
        "{err}"
    );
    assert_eq!(
        std::fs::read(&named_pbrt).expect("kept"),
        std::fs::read(dir.join("lights.json")).expect("lights")
    );
    let o = fenestra(&["relight", "render", s(&tmp("nothing")), "-o", s(&out)]);
    assert!(String::from_utf8_lossy(&o.stderr)
        .contains("not a folder made by `fenestra relight precompute`"));
}

/// A minimal HTTP/1.1 client (WebDriver speaks JSON over HTTP): (status, body).
fn http(method: &str, url: &str, body: Option<&str>) -> (u16, String) {
    let rest = url.strip_prefix("http://").expect("http url");
    let (host, path) = rest.split_at(rest.find('/').unwrap_or(rest.len()));
    let mut stream = TcpStream::connect(host).expect("connect");
    stream
        .set_read_timeout(Some(Duration::from_secs(60)))
        .expect("timeout");
    let body = body.unwrap_or("");
    write!(
        stream,
        "{method} {} HTTP/1.1\r\nHost: {host}\r\nContent-Type: application/json\r\nContent-Length: {}\r\nConnection: close\r\n\r\n{body}",
        if path.is_empty() { "/" } else { path },
        body.len()
    )
    .expect("send");
    // The head, then the body by its length, its chunks, or up to the end of the stream.
    let mut reader = BufReader::new(stream);
    let mut head = String::new();
    loop {
        let mut line = String::new();
        reader.read_line(&mut line).expect("read");
        if line == "\r\n" || line.is_empty() {
            break;
        }
        head.push_str(&line);
    }
    let status = head
        .split_whitespace()
        .nth(1)
        .and_then(|c| c.parse().ok())
        .expect("status");
    let header = |name: &str| {
        head.lines().find_map(|l| {
            l.split_once(':')
                .filter(|(k, _)| k.eq_ignore_ascii_case(name))
                .map(|(_, v)| v.trim().to_string())
        })
    };
    let mut body = Vec::new();
    if let Some(n) = header("content-length").and_then(|v| v.parse::<usize>().ok()) {
        body.resize(n, 0);
        reader.read_exact(&mut body).expect("body");
    } else if header("transfer-encoding").is_some_and(|v| v.eq_ignore_ascii_case("chunked")) {
        loop {
            let mut size = String::new();
            reader.read_line(&mut size).expect("chunk size");
            let n = usize::from_str_radix(size.trim(), 16).expect("chunk size");
            let mut chunk = vec![0; n + 2];
            reader.read_exact(&mut chunk).expect("chunk");
            if n == 0 {
                break;
            }
            body.extend_from_slice(&chunk[..n]);
        }
    } else {
        reader.read_to_end(&mut body).expect("body");
    }
    let payload = String::from_utf8_lossy(&body).into_owned();
    (status, payload)
}

/// A WebDriver session of headless Chromium.
struct Browser {
    driver: Child,
    base: String,
}

impl Browser {
    fn command(&self, method: &str, path: &str, body: serde_json::Value) -> serde_json::Value {
        let (status, text) = http(
            method,
            &format!("{}{path}", self.base),
            Some(&body.to_string()),
        );
        let v: serde_json::Value = serde_json::from_str(&text).unwrap_or(serde_json::Value::Null);
        assert!(status == 200, "{method} {path}: {status} {text}");
        v["value"].clone()
    }
    fn script(&self, js: &str) -> serde_json::Value {
        self.command(
            "POST",
            "/execute/sync",
            serde_json::json!({ "script": js, "args": [] }),
        )
    }
    /// Waits until `js` returns true.
    fn until(&self, js: &str, what: &str) {
        let start = Instant::now();
        while self.script(js) != serde_json::json!(true) {
            assert!(
                start.elapsed() < Duration::from_secs(60),
                "timed out waiting for {what}"
            );
            std::thread::sleep(Duration::from_millis(100));
        }
    }
}

impl Drop for Browser {
    fn drop(&mut self) {
        let _ = http("DELETE", &self.base, None);
        let _ = self.driver.kill();
        let _ = self.driver.wait();
    }
}

/// Chromium and ChromeDriver, where they are installed.
fn browser() -> Option<(PathBuf, PathBuf)> {
    let find = |names: &[&str]| names.iter().map(PathBuf::from).find(|p| p.exists());
    Some((
        find(&[
            "/usr/bin/chromium",
            "/usr/bin/chromium-browser",
            "/usr/bin/google-chrome",
        ])?,
        find(&["/usr/bin/chromedriver", "/usr/lib/chromium/chromedriver"])?,
    ))
}

fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0")
        .expect("bind")
        .local_addr()
        .expect("addr")
        .port()
}

#[test]
fn the_page_relights_when_a_light_is_moved_and_matches_relight_render() {
    let Some((chromium, chromedriver)) = browser() else {
        eprintln!(
            "SKIPPED: no Chromium and ChromeDriver (Debian: apt-get install chromium chromium-driver; scripts/setup installs them)"
        );
        return;
    };
    let dir = tmp("page");
    ok(&precompute(&dir, &["--quiet"]));
    let (mut server, url) = serve(&dir, Stdio::null());
    let state: serde_json::Value =
        serde_json::from_str(&http("GET", &format!("{url}state"), None).1).expect("state");

    let port = free_port();
    let driver = Command::new(&chromedriver)
        .arg(format!("--port={port}"))
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("chromedriver");
    let start = Instant::now();
    while TcpStream::connect(("127.0.0.1", port)).is_err() {
        assert!(
            start.elapsed() < Duration::from_secs(30),
            "chromedriver did not start"
        );
        std::thread::sleep(Duration::from_millis(50));
    }
    let profile = tmp("chromium-profile");
    let (status, text) = http(
        "POST",
        &format!("http://127.0.0.1:{port}/session"),
        Some(
            &serde_json::json!({ "capabilities": { "alwaysMatch": { "browserName": "chrome",
                "goog:chromeOptions": { "binary": chromium, "args": [
                    "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                    "--disable-background-networking", "--disable-component-update", "--disable-sync",
                    format!("--user-data-dir={}", profile.display())] } } } })
            .to_string(),
        ),
    );
    assert_eq!(status, 200, "new session: {text}");
    let session: serde_json::Value = serde_json::from_str(&text).expect("session");
    let id = session["value"]["sessionId"].as_str().expect("session id");
    let browser = Browser {
        driver,
        base: format!("http://127.0.0.1:{port}/session/{id}"),
    };

    browser.command("POST", "/url", serde_json::json!({ "url": url }));
    browser.until(
        "return document.body.dataset.shown === '1'",
        "the first frame",
    );
    let before = browser.script("return document.getElementById('view').src");
    // Move light 0 through its x field, as a user types a new value and presses Enter.
    let field = browser.command(
        "POST",
        "/element",
        serde_json::json!({ "using": "css selector", "value": "#light-0-x" }),
    );
    let element = field
        .as_object()
        .and_then(|o| o.values().next())
        .and_then(|v| v.as_str())
        .expect("element")
        .to_string();
    browser.command(
        "POST",
        &format!("/element/{element}/clear"),
        serde_json::json!({}),
    );
    browser.command(
        "POST",
        &format!("/element/{element}/value"),
        serde_json::json!({ "text": "4.6\u{E007}" }),
    );
    browser.until(
        "return window.shown !== null && window.shown.lights[0].position[0] === 4.6",
        "the frame with the light moved",
    );
    let after = browser.script("return document.getElementById('view').src");
    assert_ne!(before, after, "the picture did not change");
    assert!(
        browser.script("return document.getElementById('error').textContent")
            == serde_json::json!("")
    );

    // The page shows what `relight render` writes for the same frame and lights.
    let shown = browser.script("return window.shown");
    let frame = shown["frame"].as_u64().expect("frame");
    let lights = tmp("page-lights.json");
    std::fs::write(
        &lights,
        serde_json::json!({ "lights": shown["lights"] }).to_string(),
    )
    .expect("lights");
    let out = tmp("page-render");
    let ev = state["exposure"].to_string();
    ok(&fenestra(&[
        "relight",
        "render",
        s(&dir),
        "--lights",
        s(&lights),
        "--frames",
        &format!("{frame}..{}", frame + 1),
        "--exposure",
        &ev,
        "-o",
        s(&out),
        "--quiet",
    ]));
    let png = std::fs::read(out.join(format!("frame-{frame:04}.png"))).expect("png");
    let data_url = after.as_str().expect("data URL");
    assert_eq!(
        data_url,
        format!("data:image/png;base64,{}", base64(&png)),
        "the page's frame differs from relight render's"
    );
    drop(browser);
    let _ = server.kill();
    let _ = server.wait();
}

/// Standard base64 with padding.
/// A precomputation without frame 0 serves the frames it has and says how many; a request
/// too large, or with too many lights, is refused at once.
#[test]
fn serve_offers_the_frames_precomputed_and_bounds_requests() {
    let dir = tmp("partial");
    ok(&precompute(&dir, &["--quiet", "--frames", "1..3"]));
    let (mut server, url) = serve(&dir, Stdio::piped());
    let state: serde_json::Value =
        serde_json::from_str(&http("GET", &format!("{url}state"), None).1).expect("state");
    assert_eq!(state["frames"], 3);
    assert_eq!(state["available"], serde_json::json!([1, 2]));
    let lights = &state["lights"];
    let frame = |f: u32, lights: &serde_json::Value| {
        http(
            "POST",
            &format!("{url}frame"),
            Some(&serde_json::json!({ "frame": f, "lights": lights }).to_string()),
        )
    };
    assert_eq!(frame(1, lights).0, 200);
    let (status, why) = frame(0, lights);
    assert_eq!(status, 400, "{why}");
    let many = serde_json::json!({ "lights": vec![lights["lights"][0].clone(); 300] });
    let (status, why) = frame(1, &many);
    assert!(
        status == 400 && why.contains("at most 256 lights"),
        "{status} {why}"
    );
    let huge = "x".repeat((1 << 20) + 100);
    let (status, why) = http("POST", &format!("{url}frame"), Some(&huge));
    assert!(
        status == 400 && why.contains("larger than"),
        "{status} {why}"
    );
    let _ = server.kill();
    let mut err = String::new();
    let _ = std::io::Read::read_to_string(&mut server.stderr.take().expect("stderr"), &mut err);
    let _ = server.wait();
    assert!(err.contains("2 of its 3 frames precomputed"), "{err}");
}

/// `fenestra relight serve DIR` on a free port, its stderr to `stderr`: the process and the
/// URL it serves.
fn serve(dir: &Path, stderr: Stdio) -> (std::process::Child, String) {
    let mut server = Command::new(env!("CARGO_BIN_EXE_fenestra"))
        .args(["relight", "serve", s(dir), "--port", "0"])
        .stdout(Stdio::piped())
        .stderr(stderr)
        .spawn()
        .expect("serve");
    let mut line = String::new();
    BufReader::new(server.stdout.take().expect("stdout"))
        .read_line(&mut line)
        .expect("address");
    let url = line.trim().strip_prefix("serving ").expect("serving URL");
    (server, url.to_string())
}

fn base64(bytes: &[u8]) -> String {
    const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for c in bytes.chunks(3) {
        let n = (c[0] as u32) << 16
            | (*c.get(1).unwrap_or(&0) as u32) << 8
            | *c.get(2).unwrap_or(&0) as u32;
        for k in 0..4 {
            if k <= c.len() {
                out.push(A[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}
