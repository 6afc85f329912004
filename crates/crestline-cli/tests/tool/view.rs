//! The `view` command's HTML, opened as its users open it: in a browser (Debian's
//! Chromium, headless, with networking off), which must run it without an error and
//! show the surface and each family of lines in its colour.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::crestline;
use resvg::tiny_skia::Pixmap;

/// Debian's Chromium (`.ci/run` installs it), or `None` with a message: the test
/// is then skipped.
fn chromium() -> Option<PathBuf> {
    let found = ["/usr/bin/chromium", "/usr/bin/chromium-browser"]
        .into_iter()
        .map(PathBuf::from)
        .find(|p| p.is_file());
    if found.is_none() {
        common::skip("no Chromium at /usr/bin/chromium (apt-get install chromium)");
    }
    found
}

/// Chromium headless on `page` (a file, with the URL fragment `fragment`), no GPU
/// (WebGL by SwiftShader) and no network, with `what` (`--dump-dom` or
/// `--screenshot=FILE`); its standard output, and the page's console messages.
fn open(
    browser: &Path,
    page: &Path,
    fragment: &str,
    what: &str,
    profile: &Path,
) -> (String, Vec<String>) {
    let url = format!("file://{}{fragment}", page.display());
    let out = Command::new(browser)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--use-angle=swiftshader",
            "--enable-unsafe-swiftshader",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            // Networking off: every name fails to resolve, every proxied request
            // goes nowhere.
            "--host-resolver-rules=MAP * ~NOTFOUND",
            "--proxy-server=127.0.0.1:9",
            "--window-size=800,600",
            "--enable-logging=stderr",
            "--v=0",
            "--virtual-time-budget=30000",
            &format!("--user-data-dir={}", profile.display()),
            what,
            &url,
        ])
        .output()
        .expect("Chromium runs");
    let log = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{log}");
    let console = log
        .lines()
        .filter(|line| line.contains(":CONSOLE"))
        .map(str::to_string)
        .collect();
    (String::from_utf8_lossy(&out.stdout).into_owned(), console)
}

/// The pixels of the screenshot outside the panel (its top left corner, whose
/// swatches show every family's colour).
fn scene_pixels(shot: &Pixmap) -> impl Iterator<Item = &resvg::tiny_skia::PremultipliedColorU8> {
    let width = shot.width() as usize;
    shot.pixels()
        .iter()
        .enumerate()
        .filter(move |(n, _)| n % width >= 240 || n / width >= 120)
        .map(|(_, p)| p)
}

/// Pixels of the scene near `color` (within 60 in RGB distance).
fn count_near(shot: &Pixmap, color: [u8; 3]) -> usize {
    scene_pixels(shot)
        .filter(|p| {
            let d = [p.red(), p.green(), p.blue()]
                .iter()
                .zip(color)
                .map(|(&a, b)| (f64::from(a) - f64::from(b)).powi(2))
                .sum::<f64>();
            d.sqrt() < 60.0
        })
        .count()
}

/// Pixels of the lit grey surface: neutral, neither white nor black.
fn count_grey(shot: &Pixmap) -> usize {
    scene_pixels(shot)
        .filter(|p| {
            let (r, g, b) = (
                i32::from(p.red()),
                i32::from(p.green()),
                i32::from(p.blue()),
            );
            (r - g).abs() < 8 && (g - b).abs() < 8 && (70..235).contains(&r)
        })
        .count()
}

const RIDGE_RED: [u8; 3] = [0xc0, 0x39, 0x2b];
const VALLEY_BLUE: [u8; 3] = [0x24, 0x71, 0xa3];

/// Writes the view of `input` (with `args`), checks that it runs to its end in the
/// browser, and returns the screenshots as shown and with `hide` hidden.
fn shots(input: &str, args: &[&str], hide: &str, dir: &Path) -> Option<(Pixmap, Pixmap)> {
    let browser = chromium()?;
    let page = dir.join("view.html");
    let mut command = vec!["view", input, "-o", page.to_str().unwrap()];
    command.extend_from_slice(args);
    let out = crestline(&command);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let hidden = format!("#hide={hide}");
    for fragment in ["", hidden.as_str()] {
        let (dom, console) = open(
            &browser,
            &page,
            fragment,
            "--dump-dom",
            &dir.join("profile"),
        );
        let start = &dom[..dom.len().min(2000)];
        assert!(
            dom.contains("data-ready=\"true\""),
            "the viewer did not finish ({fragment}):\n{start}"
        );
        assert!(
            !dom.contains("data-error"),
            "the viewer failed ({fragment}):\n{start}"
        );
        // SwiftShader's own performance notes are not the page's.
        let page_messages: Vec<&String> = console
            .iter()
            .filter(|line| !line.contains("GL Driver Message"))
            .collect();
        assert!(
            page_messages.is_empty(),
            "console ({fragment}): {page_messages:#?}"
        );
    }
    let shot = |fragment: &str, name: &str| {
        let file = dir.join(name);
        let what = format!("--screenshot={}", file.display());
        open(&browser, &page, fragment, &what, &dir.join("profile"));
        Pixmap::load_png(&file).expect("a PNG screenshot")
    };
    Some((shot("", "shown.png"), shot(&hidden, "hidden.png")))
}

/// The pixels of ridge red, valley blue and surface grey in the scene of `shot`,
/// checked to be above `floors`.
fn colours_above(shot: &Pixmap, floors: [usize; 3]) -> [usize; 3] {
    let counts = [
        count_near(shot, RIDGE_RED),
        count_near(shot, VALLEY_BLUE),
        count_grey(shot),
    ];
    let above = counts
        .iter()
        .zip(floors)
        .all(|(&count, floor)| count > floor);
    assert!(above, "red, blue, grey {counts:?}, floors {floors:?}");
    counts
}

#[test]
fn the_bunnys_view_shows_the_surface_ridges_and_valleys_and_toggles_them() {
    let dir = tempfile::tempdir().unwrap();
    let Some((shown, hidden)) = shots("meshes/bunny.obj", &[], "ridges", dir.path()) else {
        return;
    };
    let [red, blue, _] = colours_above(&shown, [300, 300, 30_000]);
    // Hiding the ridges removes their red and leaves the valleys.
    let red_hidden = count_near(&hidden, RIDGE_RED);
    assert!(red_hidden < red / 20, "red {red} -> {red_hidden}");
    assert!(count_near(&hidden, VALLEY_BLUE) > blue / 2);
}

#[test]
fn the_templates_crest_lines_show_on_its_isosurface() {
    let dir = tempfile::tempdir().unwrap();
    let args = ["--level", "60", "--lines", "crest"];
    let input = "volumes/mni152_t1_1mm.nii.gz";
    let Some((shown, hidden)) = shots(input, &args, "ridges,valleys", dir.path()) else {
        return;
    };
    let [red, blue, _] = colours_above(&shown, [1000, 1000, 30_000]);
    assert!(count_near(&hidden, RIDGE_RED) < red / 20);
    assert!(count_near(&hidden, VALLEY_BLUE) < blue / 20);
}
