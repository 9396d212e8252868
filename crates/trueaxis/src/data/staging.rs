//! The prepare phase of an [`OutputSet`] (its module documentation): every output checked, its
//! contents written and synced to a temporary beside its target (a fresh temporary directory for
//! a directory output), streamed outputs opened for the caller. Nothing here touches a final path:
//! a failure drops the temporaries, and directories made for the run are removed again.

use super::commit::{PreparedSet, Sink, StagedDirectory, StagedFile};
use super::output_set::{Contents, DirectoryOutput, OutputSet};
use super::target::{keep_owner, open_standard_output, open_stream, refuse_unwritable, target_of, Target};
use super::temporaries::{affixes, clean_abandoned, is_temporary_name, LiveTemporary};
use super::DataError;
use crate::files::inputs::{input_at, FileIdentity};
use std::collections::BTreeSet;
use std::io::Write;
use std::path::{Component, Path, PathBuf};

pub(super) fn prepare(set: OutputSet) -> Result<PreparedSet, DataError> {
    let mut created = Vec::new();
    let result = stage_all(set, &mut created);
    if result.is_err() {
        // the temporaries went with their handles; directories made for the run go too, deepest
        // first, and only when empty
        for dir in created.iter().rev() {
            let _ = std::fs::remove_dir(dir);
        }
    }
    result
}

fn stage_all(set: OutputSet, created: &mut Vec<PathBuf>) -> Result<PreparedSet, DataError> {
    let mut seen = BTreeSet::new();
    for path in set.paths() {
        if !seen.insert(path.clone()) {
            return Err(invalid(&path, "given for two outputs of the same run"));
        }
    }
    for dir in &set.parents {
        create_missing(dir, created).map_err(write_error(dir))?;
    }
    let mut prepared = PreparedSet::default();
    let checked = !set.updates_inputs;
    for d in set.directories {
        stage_directory(d, checked, created, &mut prepared)?;
    }
    for (path, contents) in set.files {
        stage_file(path, contents, checked, &mut prepared)?;
    }
    Ok(prepared)
}

pub(super) fn invalid(path: &Path, message: &str) -> DataError {
    DataError::Invalid { origin: super::output_name(path), message: message.to_string() }
}

pub(super) fn write_error(path: &Path) -> impl Fn(std::io::Error) -> DataError {
    let name = super::output_name(path);
    move |source| DataError::Write { path: name.clone(), source: without_temporary_path(source) }
}

/// The directory holding `path` (`.` for a bare name).
pub(super) fn parent_of(path: &Path) -> &Path {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
}

/// A builder of temporary files (`directory == false`, mode `0666 & !umask`) or directories
/// (`0777 & !umask`) named `prefix...suffix`.
pub(super) fn temporary_builder<'a>(prefix: &'a str, suffix: &'static str, directory: bool) -> tempfile::Builder<'a, 'static> {
    let mut builder = tempfile::Builder::new();
    builder.prefix(prefix).suffix(suffix);
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(if directory { 0o777 } else { 0o666 }));
    }
    #[cfg(not(unix))]
    let _ = directory;
    builder
}

/// The name of `path`'s last component, for the names of its temporaries.
fn target_name(path: &Path) -> Result<String, DataError> {
    match path.file_name() {
        Some(n) => Ok(n.to_string_lossy().into_owned()),
        None => Err(invalid(path, "not a file or directory name (give a path that ends in a name)")),
    }
}

/// Refuses an output that is an input this run read (or a directory replaced whole that holds
/// one): the late twin of the command line's check of its arguments (`inputs`).
fn refuse_input(given: &Path, target: &Path, whole_directory: bool) -> Result<(), DataError> {
    let Some(identity) = FileIdentity::of(target) else { return Ok(()) };
    match input_at(&identity, whole_directory) {
        None => Ok(()),
        Some(input) => {
            let what = if whole_directory { "is a directory this run replaces whole, and it holds" } else { "is" };
            Err(invalid(
                given,
                &format!(
                    "{what} the input {} of this run: writing it would destroy the input; choose another output path",
                    input.display()
                ),
            ))
        }
    }
}

/// A buffered writer of a file that is synced at commit.
fn file_sink(path: &Path, file: std::fs::File) -> std::io::Result<Sink> {
    let durable = file.try_clone()?;
    Ok(Sink::new(path, Box::new(file), Some(durable)))
}

/// Stages the single file `path`: a temporary beside a regular target (written now, or opened for
/// the caller), or a stream written in place.
fn stage_file(path: PathBuf, contents: Contents, inputs_checked: bool, prepared: &mut PreparedSet) -> Result<(), DataError> {
    let err = write_error(&path);
    let (target, existing) = match target_of(&path)? {
        Target::File { path: target, existing } => (target, existing),
        Target::StandardOutput => return stage_in_place(path, None, contents, prepared),
        Target::Stream { path: device } => return stage_in_place(path, Some(device), contents, prepared),
    };
    let name = target_name(&target)?;
    if existing.is_some() {
        if inputs_checked {
            refuse_input(&path, &target, false)?;
        }
        refuse_unwritable(&path, &target)?;
    }
    let dir = parent_of(&target);
    clean_abandoned(dir, &name);
    let (prefix, suffix) = affixes(&name);
    let mut tmp = temporary_builder(&prefix, suffix, false).tempfile_in(dir).map_err(&err)?;
    let live = LiveTemporary::register(tmp.path());
    if let Some(existing) = &existing {
        tmp.as_file().set_permissions(existing.permissions()).map_err(&err)?;
        keep_owner(tmp.as_file(), existing);
    }
    match contents {
        Contents::Bytes(bytes) => {
            tmp.write_all(&bytes).map_err(&err)?;
            tmp.as_file().sync_all().map_err(&err)?;
        }
        Contents::Streamed => prepared.sinks.push(file_sink(&path, tmp.as_file().try_clone().map_err(&err)?).map_err(&err)?),
    }
    prepared.files.push(StagedFile::Renamed { given: path, target, tmp, live });
    Ok(())
}

/// Stages an output written in place: standard output (`device` none) or a device, FIFO or path
/// through a descriptor. Given contents wait for the commit; a streamed one is opened now.
fn stage_in_place(path: PathBuf, device: Option<PathBuf>, contents: Contents, prepared: &mut PreparedSet) -> Result<(), DataError> {
    match contents {
        Contents::Bytes(bytes) => prepared.files.push(StagedFile::InPlace { given: path, device, bytes }),
        Contents::Streamed => {
            let writer = open_in_place(device.as_deref()).map_err(write_error(&path))?;
            prepared.sinks.push(Sink::new(&path, writer, None));
        }
    }
    Ok(())
}

/// Opens an output written in place (standard output when `device` is none).
pub(super) fn open_in_place(device: Option<&Path>) -> std::io::Result<Box<dyn Write + Send>> {
    match device {
        None => open_standard_output(),
        Some(d) => Ok(Box::new(open_stream(d)?)),
    }
}

/// Checks the directory output and writes its files into a fresh temporary directory beside it
/// (missing parents are created and recorded in `created`); streamed files are opened there.
fn stage_directory(
    output: DirectoryOutput,
    inputs_checked: bool,
    created: &mut Vec<PathBuf>,
    prepared: &mut PreparedSet,
) -> Result<(), DataError> {
    let mut relative = Vec::new();
    for (r, _) in &output.files {
        if r.as_os_str().is_empty() || !r.components().all(|c| matches!(c, Component::Normal(_))) {
            return Err(invalid(&output.path.join(r), "not a path of names inside the output directory"));
        }
        relative.push(r.clone());
    }
    let (target, exists, name) = check_directory_target(&output.path)?;
    if exists {
        if inputs_checked {
            refuse_input(&output.path, &target, true)?;
        }
        refuse_foreign_files(&output.path, &target, &relative)?;
    }
    let parent = parent_of(&target).to_path_buf();
    create_missing(&parent, created).map_err(write_error(&parent))?;
    clean_abandoned(&parent, &name);
    let err = write_error(&output.path);
    let (prefix, suffix) = affixes(&name);
    let staging = temporary_builder(&prefix, suffix, true).tempdir_in(&parent).map_err(&err)?;
    let live = LiveTemporary::register(staging.path());
    if exists {
        let mode = std::fs::metadata(&target).map_err(&err)?.permissions();
        std::fs::set_permissions(staging.path(), mode).map_err(&err)?;
    }
    for (r, contents) in output.files {
        let path = staging.path().join(&r);
        let final_path = output.path.join(&r);
        let err = write_error(&final_path);
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir).map_err(&err)?;
        }
        let mut file = std::fs::File::create(&path).map_err(&err)?;
        if exists {
            if let Ok(old) = std::fs::metadata(target.join(&r)) {
                file.set_permissions(old.permissions()).map_err(&err)?;
            }
        }
        match contents {
            Contents::Bytes(bytes) => {
                file.write_all(&bytes).map_err(&err)?;
                file.sync_all().map_err(&err)?;
            }
            Contents::Streamed => prepared.sinks.push(file_sink(&final_path, file).map_err(&err)?),
        }
    }
    prepared.directories.push(StagedDirectory { given: output.path, target, staging, live, relative, exists });
    Ok(())
}

/// The target of a directory output `given`: the directory with symbolic links and `.` resolved
/// (so that the swap replaces the directory itself, not a link to it), whether it exists, and its
/// name. Refuses standard output, a path that is not a directory, and a directory this user may
/// not write.
pub(super) fn check_directory_target(given: &Path) -> Result<(PathBuf, bool, String), DataError> {
    if super::is_standard_output(given) {
        return Err(invalid(given, "names standard output, but this output is a directory; give the path of a directory"));
    }
    let exists = given.exists();
    let target = if exists { given.canonicalize().map_err(write_error(given))? } else { given.to_path_buf() };
    if exists && !target.is_dir() {
        return Err(invalid(given, "exists and is not a directory; give the path of a directory"));
    }
    if exists {
        refuse_unwritable(given, &target)?;
    }
    let name = target_name(&target)?;
    Ok((target, exists, name))
}

/// Refuses the staged directory `d` when its existing target holds files it does not write.
pub(super) fn refuse_foreign_in(d: &StagedDirectory) -> Result<(), DataError> {
    if d.exists {
        refuse_foreign_files(&d.given, &d.target, &d.relative)?;
    }
    Ok(())
}

/// Creates `dir` and its missing parents, recording each one created (outermost first). A
/// directory another run creates at the same moment is taken as it is.
pub(super) fn create_missing(dir: &Path, created: &mut Vec<PathBuf>) -> std::io::Result<()> {
    let missing: Vec<&Path> = dir.ancestors().take_while(|d| !d.as_os_str().is_empty() && !d.exists()).collect();
    for d in missing.into_iter().rev() {
        match std::fs::create_dir(d) {
            Ok(()) => created.push(d.to_path_buf()),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists && d.is_dir() => {}
            Err(e) => return Err(e),
        }
    }
    Ok(())
}

/// Refuses a directory output that holds anything but files of this set (and temporaries): the
/// swap replaces the whole directory, and a user's file must never go with it; a stale table of
/// another run must not stay next to the new ones either.
pub(super) fn refuse_foreign_files(given: &Path, target: &Path, relative: &[PathBuf]) -> Result<(), DataError> {
    let wanted: BTreeSet<&Path> = relative.iter().map(|p| p.as_path()).collect();
    let mut foreign = Vec::new();
    collect_foreign(target, Path::new(""), &wanted, &mut foreign).map_err(write_error(given))?;
    if foreign.is_empty() {
        return Ok(());
    }
    foreign.sort();
    Err(invalid(
        given,
        &format!(
            "the output directory holds files this run does not write ({}); use an empty or new directory so that tables \
             of different runs do not mix",
            foreign.join(" ")
        ),
    ))
}

fn collect_foreign(root: &Path, below: &Path, wanted: &BTreeSet<&Path>, foreign: &mut Vec<String>) -> std::io::Result<()> {
    for entry in std::fs::read_dir(root.join(below))? {
        let entry = entry?;
        let name = entry.file_name();
        if name.to_str().is_some_and(is_temporary_name) {
            continue;
        }
        let relative = below.join(&name);
        if entry.file_type()?.is_dir() {
            if wanted.iter().any(|w| w.starts_with(&relative) && *w != relative) {
                collect_foreign(root, &relative, wanted, foreign)?;
            } else {
                foreign.push(format!("{}/", relative.display()));
            }
        } else if !wanted.contains(relative.as_path()) {
            foreign.push(relative.display().to_string());
        }
    }
    Ok(())
}

/// The system error without the name of the temporary file that `tempfile` appends to it (`... at
/// path "/dir/.X.trueaxis-...tmp"`): the user asked for the final path, which the message names.
fn without_temporary_path(e: std::io::Error) -> std::io::Error {
    let text = e.to_string();
    match text.rfind(" at path \"") {
        Some(i) if e.raw_os_error().is_none() => std::io::Error::new(e.kind(), text[..i].to_string()),
        _ => e,
    }
}

#[cfg(test)]
mod tests {
    use super::super::{write_atomically, OutputSet};
    use crate::files::inputs;

    #[test]
    fn an_input_of_the_run_is_never_an_output() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("campaign");
        std::fs::create_dir(&dir).unwrap();
        let data = dir.join("station1.csv");
        std::fs::write(&data, "X,dL\n0,1\n").unwrap();
        inputs::track();
        inputs::read(&data).unwrap();
        let e = write_atomically(&dir.join("./station1.csv"), b"residuals").unwrap_err().to_string();
        assert!(e.contains("is the input") && e.contains("station1.csv"), "{e}");
        let mut set = OutputSet::new();
        set.in_directory(&dir, "station1.csv", "x");
        let e = set.commit().unwrap_err().to_string();
        assert!(e.contains("replaces whole, and it holds the input"), "{e}");
        assert_eq!(std::fs::read_to_string(&data).unwrap(), "X,dL\n0,1\n");
    }

    #[cfg(unix)]
    #[test]
    fn a_file_this_user_may_not_write_is_not_replaced() {
        use std::os::unix::fs::PermissionsExt;
        // SAFETY: geteuid has no preconditions
        if unsafe { libc::geteuid() } == 0 {
            println!("skipped: root may write any file (the command-line test runs this as another user)");
            return;
        }
        let tmp = tempfile::tempdir().unwrap();
        let file = tmp.path().join("e.toml");
        std::fs::write(&file, "old").unwrap();
        std::fs::set_permissions(&file, std::fs::Permissions::from_mode(0o444)).unwrap();
        let e = write_atomically(&file, b"new").unwrap_err();
        assert!(e.to_string().contains("this user may not write it (mode 0444"), "{e}");
        assert!(crate::files::environment_cause(&e).is_some(), "a permission error: {e}");
        assert_eq!(std::fs::read_to_string(&file).unwrap(), "old");
    }
}
