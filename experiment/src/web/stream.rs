//! A file as a stream of chunks, for response bodies: an encoded video (tens of MB) is sent as
//! it is read, so the server holds a chunk per download, not the whole file.

use axum::body::Bytes;
use std::pin::Pin;
use std::task::{Context, Poll};
use tokio::io::{AsyncRead, ReadBuf};

const CHUNK: usize = 256 * 1024;

/// The file's bytes from where it stands to its end.
pub struct Chunks {
    file: tokio::fs::File,
    buf: Vec<u8>,
}

pub fn chunks(file: tokio::fs::File) -> Chunks {
    Chunks {
        file,
        buf: vec![0; CHUNK],
    }
}

impl futures_core::Stream for Chunks {
    type Item = std::io::Result<Bytes>;

    fn poll_next(self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<Option<Self::Item>> {
        let this = self.get_mut();
        let mut read = ReadBuf::new(&mut this.buf);
        match Pin::new(&mut this.file).poll_read(cx, &mut read) {
            Poll::Pending => Poll::Pending,
            Poll::Ready(Err(e)) => Poll::Ready(Some(Err(e))),
            Poll::Ready(Ok(())) if read.filled().is_empty() => Poll::Ready(None),
            Poll::Ready(Ok(())) => Poll::Ready(Some(Ok(Bytes::copy_from_slice(read.filled())))),
        }
    }
}
