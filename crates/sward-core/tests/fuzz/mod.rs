//! The replay's tools: a seeded mutator of text and bytes, a worker that runs one input under a
//! time bound, and the seed inputs (scene keys, OBJ, GLB and PNG files made here).

use std::sync::mpsc;
use std::time::Duration;

use sward_core::Scene;

/// Seeded mutations (xorshift), so every input replays from its index.
pub struct Mutator {
    state: u64,
}

/// Numbers at the edges of what a value can mean.
const EXTREMES: [&str; 8] = ["1e30", "-1e30", "nan", "inf", "-inf", "0", "-1", "1e-30"];
/// Tokens that parsers meet at their edges (besides `EXTREMES`).
const TEXT_TOKENS: [&str; 16] = [
    "[",
    "]",
    "=",
    "\"",
    ",",
    "\n",
    ".",
    "{",
    "}",
    "#",
    "99999999999",
    "[[collider]]",
    "[camera]",
    "true",
    "4294967296",
    "0.0",
];
/// `--set` values besides `EXTREMES`: plain, mistyped and wrong-length ones, and pairs with
/// one extreme (a field of 24 × 1e-30 units has no room for its blades: growing it panicked).
const VALUES: [&str; 15] = [
    "[24.0, 1e-30]",
    "[1e-6, 24.0]",
    "[1e30, 1e-30]",
    "3",
    "0.5",
    "[1.0, 2.0]",
    "[1.0, 2.0, 3.0, 4.0, 5.0]",
    "[]",
    "\"on\"",
    "x",
    "true",
    "[0.0, 0.0, 0.0]",
    "[2.0, 1.0]",
    "65536",
    "-0.0",
];

impl Mutator {
    pub fn new(seed: u64) -> Mutator {
        Mutator {
            state: seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1,
        }
    }

    fn next(&mut self) -> u64 {
        self.state ^= self.state << 13;
        self.state ^= self.state >> 7;
        self.state ^= self.state << 17;
        self.state
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }

    /// A token to put into text: one of `TEXT_TOKENS` or `EXTREMES`.
    fn token(&mut self) -> &'static str {
        let k = self.below(TEXT_TOKENS.len() + EXTREMES.len());
        TEXT_TOKENS
            .get(k)
            .copied()
            .unwrap_or_else(|| EXTREMES[k - TEXT_TOKENS.len()])
    }

    /// One of `seeds`, changed one to four times: a character changed, a run deleted or
    /// repeated, a token inserted, a number replaced by an extreme, lines spliced from another
    /// seed.
    pub fn text(&mut self, seeds: &[&str]) -> String {
        let mut text: Vec<char> = seeds[self.below(seeds.len())].chars().collect();
        for _ in 0..1 + self.below(4) {
            let at = self.below(text.len() + 1);
            match self.below(6) {
                0 if at < text.len() => text[at] = self.token().chars().next().unwrap(),
                1 => {
                    let end = (at + 1 + self.below(40)).min(text.len());
                    text.drain(at.min(end)..end);
                }
                2 => {
                    let end = (at + 1 + self.below(80)).min(text.len());
                    let run: Vec<char> = text[at.min(end)..end].to_vec();
                    text.splice(at..at, run);
                }
                3 => {
                    let token = self.token();
                    text.splice(at..at, token.chars());
                }
                4 => self.replace_number(&mut text),
                _ => {
                    let other: Vec<&str> = seeds[self.below(seeds.len())].lines().collect();
                    let line = other[self.below(other.len())];
                    let lines: Vec<String> = text.iter().collect::<String>().lines().map(String::from).collect();
                    let at = self.below(lines.len() + 1);
                    let mut lines = lines;
                    lines.insert(at, line.to_string());
                    text = lines.join("\n").chars().collect();
                }
            }
        }
        text.into_iter().collect()
    }

    /// A number in `text` (the first digit at or after a random place, with its run) replaced
    /// by an extreme or odd value.
    fn replace_number(&mut self, text: &mut Vec<char>) {
        let from = self.below(text.len());
        let Some(start) = (from..text.len()).find(|&i| text[i].is_ascii_digit()) else {
            return;
        };
        let end = (start..text.len())
            .find(|&i| !(text[i].is_ascii_digit() || text[i] == '.' || text[i] == 'e' || text[i] == '-'))
            .unwrap_or(text.len());
        let value = EXTREMES[self.below(EXTREMES.len())];
        text.splice(start..end, value.chars());
    }

    /// One of `seeds`, its bytes changed one to four times: flipped, a run deleted or repeated,
    /// cut short, or a 32-bit word (a length, a count, an offset) set to an extreme.
    pub fn bytes(&mut self, seeds: &[Vec<u8>]) -> Vec<u8> {
        let mut bytes = seeds[self.below(seeds.len())].clone();
        for _ in 0..1 + self.below(4) {
            let at = self.below(bytes.len() + 1);
            match self.below(6) {
                0 if at < bytes.len() => bytes[at] ^= 1 << self.below(8),
                1 => {
                    let end = (at + 1 + self.below(16)).min(bytes.len());
                    bytes.drain(at.min(end)..end);
                }
                2 => {
                    let end = (at + 1 + self.below(32)).min(bytes.len());
                    let run = bytes[at.min(end)..end].to_vec();
                    bytes.splice(at..at, run);
                }
                3 => bytes.truncate(at),
                4 if at + 4 <= bytes.len() => {
                    let word: [u32; 5] = [0, 1, 0x7fff_ffff, 0xffff_ffff, 0x1000_0000];
                    bytes[at..at + 4].copy_from_slice(&word[self.below(5)].to_le_bytes());
                }
                _ if at < bytes.len() => bytes[at] = self.next() as u8,
                _ => {}
            }
        }
        bytes
    }

    /// One to three `--set` overrides of `keys`: extreme, odd or mistyped values.
    pub fn sets(&mut self, keys: &[String]) -> Vec<(String, String)> {
        (0..1 + self.below(3))
            .map(|_| {
                let key = keys[self.below(keys.len())].clone();
                let k = self.below(EXTREMES.len() + VALUES.len());
                let value = EXTREMES
                    .get(k)
                    .unwrap_or_else(|| &VALUES[k - EXTREMES.len()])
                    .to_string();
                (key, value)
            })
            .collect()
    }
}

/// Runs inputs one at a time on another thread, each under a time bound.
pub struct Worker {
    bound: Duration,
}

impl Worker {
    pub fn new(bound: Duration) -> Worker {
        Worker { bound }
    }

    /// `job`'s result; fails the test if it panics or runs past the bound.
    pub fn run<R: Send + 'static>(&mut self, name: &str, job: impl FnOnce() -> R + Send + 'static) -> R {
        let (tx, rx) = mpsc::channel();
        let thread = std::thread::spawn(move || {
            let _ = tx.send(job());
        });
        match rx.recv_timeout(self.bound) {
            Ok(result) => {
                let _ = thread.join();
                result
            }
            Err(mpsc::RecvTimeoutError::Timeout) => panic!("{name} took longer than {:?}", self.bound),
            Err(mpsc::RecvTimeoutError::Disconnected) => {
                let payload = thread.join().expect_err("the job ended without a result");
                let message = payload
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
                    .unwrap_or_default();
                panic!("{name} panicked: {message}")
            }
        }
    }
}

/// Every dotted key of `scene` as `--set` takes it (`camera.position`, `collider.0.radius`).
pub fn scene_keys(scene: &Scene) -> Vec<String> {
    fn walk(prefix: &str, value: &toml::Value, out: &mut Vec<String>) {
        match value {
            toml::Value::Table(table) => {
                for (k, v) in table {
                    let key = if prefix.is_empty() {
                        k.clone()
                    } else {
                        format!("{prefix}.{k}")
                    };
                    walk(&key, v, out);
                }
            }
            toml::Value::Array(items) if items.iter().all(|i| i.is_table()) && !items.is_empty() => {
                for (i, item) in items.iter().enumerate() {
                    walk(&format!("{prefix}.{i}"), item, out);
                }
            }
            _ => out.push(prefix.to_string()),
        }
    }
    let table: toml::Value = toml::from_str(&scene.to_toml()).unwrap();
    let mut keys = Vec::new();
    walk("", &table, &mut keys);
    keys
}

/// OBJ meshes: a cube of quads, a grid with texture coordinates and normals, a lone triangle.
pub fn obj_seeds() -> Vec<Vec<u8>> {
    let cube = "o cube\nv -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n\
                f 1 2 3 4\nf 5 8 7 6\nf 1 5 6 2\nf 2 6 7 3\nf 3 7 8 4\nf 5 1 4 8\n";
    let mut grid = String::from("# grid\n");
    for j in 0..4 {
        for i in 0..4 {
            grid += &format!(
                "v {i} {} {j}\nvt {} {}\nvn 0 1 0\n",
                (i * j) as f32 * 0.1,
                i as f32 / 3.0,
                j as f32 / 3.0
            );
        }
    }
    for j in 0..3 {
        for i in 0..3 {
            let a = j * 4 + i + 1;
            grid += &format!(
                "f {a}/{a}/{a} {}/{}/{} {}/{}/{}\n",
                a + 4,
                a + 4,
                a + 4,
                a + 1,
                a + 1,
                a + 1
            );
        }
    }
    let triangle = "v 0 0 0\nv 1 0 0\nv 0 0 1\nf 1 2 3\n";
    vec![cube.into(), grid.into_bytes(), triangle.into()]
}

/// A binary glTF: one mesh of two triangles (positions, 16-bit indices) in a node of a scene.
pub fn glb_seed() -> Vec<u8> {
    let positions: [f32; 12] = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 1.0];
    let indices: [u16; 6] = [0, 2, 1, 0, 3, 2];
    let mut bin: Vec<u8> = positions.iter().flat_map(|f| f.to_le_bytes()).collect();
    bin.extend(indices.iter().flat_map(|i| i.to_le_bytes()));
    let json = format!(
        concat!(
            r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"#,
            r#""nodes":[{{"mesh":0,"translation":[0,0.5,0]}}],"#,
            r#""meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}},"indices":1}}]}}],"#,
            r#""accessors":[{{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3","min":[0,0,0],"max":[1,0,1]}},"#,
            r#"{{"bufferView":1,"componentType":5123,"count":6,"type":"SCALAR"}}],"#,
            r#""bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":48}},{{"buffer":0,"byteOffset":48,"byteLength":12}}],"#,
            r#""buffers":[{{"byteLength":{}}}]}}"#
        ),
        bin.len()
    );
    let mut json = json.into_bytes();
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut glb = Vec::with_capacity(total);
    glb.extend(b"glTF");
    glb.extend(2u32.to_le_bytes());
    glb.extend((total as u32).to_le_bytes());
    glb.extend((json.len() as u32).to_le_bytes());
    glb.extend(b"JSON");
    glb.extend(&json);
    glb.extend((bin.len() as u32).to_le_bytes());
    glb.extend(b"BIN\0");
    glb.extend(&bin);
    glb
}

/// Height maps: 8- and 16-bit grey PNGs of a small hill.
pub fn png_seeds() -> Vec<Vec<u8>> {
    let encode = |image: image::DynamicImage| {
        let mut bytes = Vec::new();
        image
            .write_to(&mut std::io::Cursor::new(&mut bytes), image::ImageFormat::Png)
            .unwrap();
        bytes
    };
    let hill = |x: u32, y: u32| 1.0 - ((x as f32 - 8.0).powi(2) + (y as f32 - 8.0).powi(2)) / 128.0;
    let grey8 = image::GrayImage::from_fn(16, 16, |x, y| image::Luma([(hill(x, y) * 255.0) as u8]));
    let grey16 = image::ImageBuffer::<image::Luma<u16>, Vec<u16>>::from_fn(12, 9, |x, y| {
        image::Luma([(hill(x, y) * 65535.0) as u16])
    });
    vec![
        encode(image::DynamicImage::ImageLuma8(grey8)),
        encode(image::DynamicImage::ImageLuma16(grey16)),
    ]
}

/// Scene files the replay found, each with the key its refusal must name.
pub const FOUND_SCENES: [(&str, &str); 8] = [
    ("[camera]\nposition = [1e30, 2.0, 3.0]\n", "camera.position"),
    ("[camera]\nup = [0.0, 0.0, 0.0]\n", "camera.up"),
    ("[camera]\nnear = 1e-30\n", "camera.near"),
    (
        "[[collider]]\ncenter = [0.0, 0.5, 0.0]\nradius = inf\n",
        "collider.0.radius",
    ),
    (
        "[[body]]\nshape = { type = \"boulder\", radius = 1e-30, seed = 4 }\nspheres = 8\ncenter = [0.0, 1.0, 0.0]\n",
        "body.shape",
    ),
    ("[wind]\nstrength = nan\n", "wind.strength"),
    // A side too thin for a row of the blades (growing it panicked; SAMPLE_BLADES reaches it).
    ("[field]\nblades = 60000\nsize = [24.0, 1e-30]\n", "field.size"),
    // A generated grid with more items within its radius than a frame can list.
    (
        "[instanced]\ndensity = 10000.0\nradius = 100000.0\n",
        "instanced.radius",
    ),
];

/// Mesh files the replay found (name, bytes), each once a panic or a refusal without the file.
pub fn found_mesh_files() -> Vec<(&'static str, Vec<u8>)> {
    // A face's texture coordinate index far out of range (the OBJ reader's arithmetic overflowed).
    let obj = "v 0 0 0\nv 1 0 0\nv 0 0 1\nvt 0 0\nf 1/9223372036854775807 2/1 3/1\n";
    // Positions declared as two floats each (the glTF reader asserted on the size).
    let mut glb = glb_seed();
    let at = glb.windows(4).position(|w| w == b"VEC3").unwrap();
    glb[at + 3] = b'2';
    // A header that states a length shorter than itself (the reader would have allocated 4 GiB).
    let mut short = glb_seed();
    short[8..12].copy_from_slice(&4u32.to_le_bytes());
    vec![
        ("index.obj", obj.as_bytes().to_vec()),
        ("positions.glb", glb),
        ("length.glb", short),
    ]
}
