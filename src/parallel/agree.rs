//! Collective agreement on errors.
//!
//! Input is read and checked by every rank; when any rank fails, all ranks must stop together
//! and the user must see one message, not one per rank and not a hang. [`agree`] is a collective
//! point: if some rank has an error, every rank returns [`Agreed`] carrying the message of the
//! lowest failing rank. Errors that happen between such points (inside a collective solve, say)
//! cannot be agreed on; `main` turns them into a message and `MPI_Abort`.
use mpi::collective::SystemOperation;
use mpi::traits::{Communicator, CommunicatorCollectives, Root};

/// An error every rank knows about: the message of the lowest failing rank.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{message}")]
pub struct Agreed {
    /// The message.
    pub message: String,
    /// The process exit code it calls for.
    pub exit_code: i32,
    /// The rank it came from.
    pub rank: usize,
}

/// Collective. Returns `r` unchanged on every rank when no rank failed; otherwise every rank
/// returns the lowest failing rank's error as [`Agreed`] (`exit_code` from `code`).
pub fn agree<T, E: std::fmt::Display>(
    comm: &impl Communicator,
    r: Result<T, E>,
    code: impl Fn(&E) -> i32,
) -> Result<T, Agreed> {
    let size = comm.size();
    let rank = comm.rank();
    let mine = if r.is_err() { rank } else { size };
    let mut first = size;
    comm.all_reduce_into(&mine, &mut first, SystemOperation::min());
    if first == size {
        return r.map_err(|_| unreachable_agreed());
    }
    let (mut bytes, mut exit_code) = match &r {
        Err(e) if rank == first => (e.to_string().into_bytes(), code(e)),
        _ => (Vec::new(), 0),
    };
    let root = comm.process_at_rank(first);
    let mut len = bytes.len() as u64;
    root.broadcast_into(&mut len);
    bytes.resize(len as usize, 0);
    root.broadcast_into(&mut bytes[..]);
    root.broadcast_into(&mut exit_code);
    Err(Agreed { message: String::from_utf8_lossy(&bytes).into_owned(), exit_code, rank: first as usize })
}

fn unreachable_agreed() -> Agreed {
    // `first == size` means no rank reported an error, this one included.
    Agreed { message: "internal error: inconsistent error agreement".into(), exit_code: 70, rank: 0 }
}
