//! Jobs for distributed engines: a chain of steps, each a fenestra command run once or once
//! per piece (its tasks), every step after the one before it has succeeded. Written as an
//! Open Job Description template (AWS Deadline Cloud's open job format; `openjd run` runs it
//! on one machine) or as Slurm batch scripts (a job array per step, chained by
//! `--dependency=afterok` in submit.sh).

use anyhow::Result;
use clap::ValueEnum;
use serde_json::json;
use std::path::{Path, PathBuf};

/// Stands in an argument for the task's piece.
pub const PIECE: &str = "{piece}";
/// Stands in an argument for the task's index.
pub const PART: &str = "{part}";

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Engine {
    /// An Open Job Description template, template.json (`openjd run`, Deadline Cloud).
    Openjd,
    /// Slurm batch scripts, one per step, and submit.sh that submits them in order.
    Slurm,
}

/// One step: fenestra run with `args` once, or once per piece with [`PIECE`] and [`PART`]
/// replaced by the piece and its index.
pub struct Step {
    /// Its name (a word: `Render`, `Merge`).
    pub name: &'static str,
    /// The arguments of fenestra.
    pub args: Vec<String>,
    /// The pieces; none for a single task.
    pub pieces: Vec<String>,
    /// Each task takes a whole machine (Slurm `--exclusive`): renders use every core.
    pub whole_machine: bool,
}

/// A job: steps run in order by one fenestra executable; its files go to `dir`.
pub struct EngineJob {
    /// What it does, for people.
    pub title: String,
    /// The fenestra executable, as the workers see it.
    pub fenestra: String,
    /// The job folder (absolute): the job's files, logs/, and whatever the steps write.
    pub dir: PathBuf,
    /// The steps, each after the one before.
    pub steps: Vec<Step>,
}

impl EngineJob {
    /// Writes the job for `engine` into its folder (made with logs/ inside); returns the
    /// files written, each with a word on what it is.
    pub fn write(&self, engine: Engine) -> Result<Vec<(PathBuf, String)>> {
        let logs = self.dir.join("logs");
        std::fs::create_dir_all(&logs)
            .map_err(|e| anyhow::anyhow!("cannot create {}: {e}", logs.display()))?;
        let files = match engine {
            Engine::Openjd => vec![(
                "template.json".to_string(),
                serde_json::to_string_pretty(&self.openjd())? + "\n",
                format!(
                    "run it here: openjd run {}/template.json --step {} --run-dependencies",
                    self.dir.display(),
                    self.last()
                ),
            )],
            Engine::Slurm => self.slurm(),
        };
        let mut written = Vec::new();
        for (name, text, how) in files {
            let path = self.dir.join(name);
            fenestra_core::fs::write_text_atomically(&path, &text)?;
            written.push((path, how));
        }
        Ok(written)
    }

    fn last(&self) -> &str {
        self.steps.last().map_or("", |s| s.name)
    }

    /// The template: the executable and the job folder (by default the template's own) are
    /// job parameters, so that a farm can map them; a step with pieces has the task
    /// parameters Part and Piece, associated.
    fn openjd(&self) -> serde_json::Value {
        let dir = self.dir.display().to_string();
        let param = |a: &str| {
            a.replace(&dir, "{{Param.JobDir}}")
                .replace(PIECE, "{{Task.Param.Piece}}")
                .replace(PART, "{{Task.Param.Part}}")
        };
        let steps: Vec<serde_json::Value> = self
            .steps
            .iter()
            .enumerate()
            .map(|(i, step)| {
                let args: Vec<String> = step.args.iter().map(|a| param(a)).collect();
                let mut s = json!({
                    "name": step.name,
                    "script": {
                        "actions": { "onRun": { "command": "{{Param.Fenestra}}", "args": args } }
                    }
                });
                if !step.pieces.is_empty() {
                    s["parameterSpace"] = json!({
                        "taskParameterDefinitions": [
                            { "name": "Part", "type": "INT", "range": format!("0-{}", step.pieces.len() - 1) },
                            { "name": "Piece", "type": "STRING", "range": step.pieces }
                        ],
                        "combination": "(Part, Piece)"
                    });
                }
                if i > 0 {
                    s["dependencies"] = json!([{ "dependsOn": self.steps[i - 1].name }]);
                }
                s
            })
            .collect();
        json!({
            "specificationVersion": "jobtemplate-2023-09",
            "name": format!("fenestra: {}", self.title),
            "parameterDefinitions": [
                {
                    "name": "Fenestra",
                    "type": "STRING",
                    "default": self.fenestra,
                    "description": "The fenestra executable, as the workers see it."
                },
                {
                    "name": "JobDir",
                    "type": "PATH",
                    "objectType": "DIRECTORY",
                    "dataFlow": "OUT",
                    "default": ".",
                    "description": "The job folder: by default the template's own."
                }
            ],
            "steps": steps
        })
    }

    /// One batch script per step (an array over its pieces) and submit.sh, which submits
    /// each after the one before with --dependency=afterok.
    fn slurm(&self) -> Vec<(String, String, String)> {
        let logs = self.dir.join("logs");
        let mut files = Vec::new();
        let mut submit = String::from(
            "#!/bin/bash\n\
             # Submits the steps in order, each to start once the one before has succeeded.\n\
             set -euo pipefail\n\
             here=$(cd \"$(dirname \"$0\")\" && pwd)\n",
        );
        for (i, step) in self.steps.iter().enumerate() {
            let name = step.name.to_lowercase();
            let mut text = format!(
                "#!/bin/bash\n# {}: step {}, written by fenestra.\n#SBATCH --job-name=fenestra-{name}\n",
                self.title, step.name
            );
            if step.whole_machine {
                text += "#SBATCH --exclusive\n";
            }
            let args: Vec<String> = step.args.iter().map(|a| shell_word(a)).collect();
            if step.pieces.is_empty() {
                text += &format!("#SBATCH --output={}/{name}.log\n", quote_path(&logs));
                text += "set -euo pipefail\n";
            } else {
                let pieces: Vec<String> = step.pieces.iter().map(|p| quote(p)).collect();
                text += &format!(
                    "#SBATCH --array=0-{}\n#SBATCH --output={}/{name}-%a.log\nset -euo pipefail\npieces=({})\n",
                    step.pieces.len() - 1,
                    quote_path(&logs),
                    pieces.join(" ")
                );
            }
            text += &format!("exec {} {}\n", quote(&self.fenestra), args.join(" "));
            let after = if i == 0 {
                String::new()
            } else {
                format!(" --dependency=afterok:\"${{step{}%%;*}}\"", i - 1)
            };
            submit += &format!("step{i}=$(sbatch --parsable{after} \"$here/{name}.sbatch\")\n");
            let what = if step.pieces.is_empty() {
                format!("step {}", step.name)
            } else {
                format!("step {}, an array of {}", step.name, step.pieces.len())
            };
            files.push((format!("{name}.sbatch"), text, what));
        }
        let ids: Vec<String> = (0..self.steps.len()).map(|i| format!("$step{i}")).collect();
        submit += &format!("echo \"submitted jobs {}\"\n", ids.join(" "));
        files.push(("submit.sh".into(), submit, "run it: bash submit.sh".into()));
        files
    }
}

/// An argument as one shell word in a Slurm array task: [`PIECE`] and [`PART`] become the
/// task's piece and index.
fn shell_word(a: &str) -> String {
    if !(a.contains(PIECE) || a.contains(PART)) {
        return quote(a);
    }
    let escaped: String = a
        .chars()
        .flat_map(|c| match c {
            '\\' | '"' | '$' | '`' => vec!['\\', c],
            c => vec![c],
        })
        .collect();
    format!(
        "\"{}\"",
        escaped
            .replace(PIECE, "${pieces[$SLURM_ARRAY_TASK_ID]}")
            .replace(PART, "$SLURM_ARRAY_TASK_ID")
    )
}

fn quote_path(p: &Path) -> String {
    quote(&p.display().to_string())
}

/// `s` as one shell word.
pub fn quote(s: &str) -> String {
    let plain = |c: char| c.is_ascii_alphanumeric() || "_./:=,+-@%".contains(c);
    if !s.is_empty() && s.chars().all(plain) {
        s.to_string()
    } else {
        format!("'{}'", s.replace('\'', "'\\''"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shell_words_survive_quoting() {
        assert_eq!(quote("builtin:box-hole"), "builtin:box-hole");
        assert_eq!(quote("a b"), "'a b'");
        assert_eq!(quote("it's"), "'it'\\''s'");
        assert_eq!(quote(""), "''");
        assert_eq!(
            shell_word("/a $b/part-{part}.exr"),
            "\"/a \\$b/part-$SLURM_ARRAY_TASK_ID.exr\""
        );
        assert_eq!(shell_word("{piece}"), "\"${pieces[$SLURM_ARRAY_TASK_ID]}\"");
    }
}
