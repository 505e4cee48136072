//! Making frames and writing them, overlapped: with more than one rayon thread, item k is
//! written on a writer thread while item k + 1 is made (a channel of one item between them, so
//! at most three are in memory); items are written in the order they were made. With one rayon
//! thread everything runs in turn on the calling thread, so one thread means one core.
//! Used by `render scene` ([`super::sequence`]) and `render job` (`job::runner`).

use anyhow::Result;

/// Make each of `items` with `make(n, item)` and hand the result to `write`, in order.
/// The first error of either side is returned; a panic on the writer thread is resumed here.
pub fn make_and_write<I, T: Send>(
    items: impl IntoIterator<Item = I>,
    mut make: impl FnMut(usize, I) -> Result<T>,
    mut write: impl FnMut(T) -> Result<()> + Send,
) -> Result<()> {
    if rayon::current_num_threads() <= 1 {
        for (n, item) in items.into_iter().enumerate() {
            write(make(n, item)?)?;
        }
        return Ok(());
    }
    let (send, receive) = std::sync::mpsc::sync_channel::<T>(1);
    std::thread::scope(|threads| {
        let writer = threads.spawn(move || -> Result<()> {
            for made in receive {
                write(made)?;
            }
            Ok(())
        });
        let made = (|| -> Result<()> {
            for (n, item) in items.into_iter().enumerate() {
                if send.send(make(n, item)?).is_err() {
                    // The writer stopped on an error, which its join below returns.
                    break;
                }
            }
            Ok(())
        })();
        drop(send);
        let written = writer
            .join()
            .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
        written.and(made)
    })
}
