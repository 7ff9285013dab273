package main

// --outputs DIR: the session's recorded outputs (scenario.outputs: the client declares the
// velocity profile at --every, and the final fields), copied after the run into DIR, each checked
// against the SHA-256 the daemon names and renamed into place.

import (
	"context"
	"crypto/sha256"
	"encoding/hex"
	"fmt"
	"io"
	"os"
	"path/filepath"
	"strings"
	"time"

	lbsolidv1 "lbsolid/v1"
)

func download(client lbsolidv1.SimulationClient, id string, file *lbsolidv1.OutputFile, dir string, timeout time.Duration) error {
	target := filepath.Join(dir, file.GetName())
	if err := os.MkdirAll(filepath.Dir(target), 0o755); err != nil {
		return err
	}
	part, err := os.CreateTemp(filepath.Dir(target), "."+filepath.Base(target)+".part-")
	if err != nil {
		return err
	}
	defer os.Remove(part.Name())
	defer part.Close()
	ctx, cancel := context.WithTimeout(context.Background(), timeout)
	defer cancel()
	stream, err := client.DownloadOutput(ctx, &lbsolidv1.DownloadOutputRequest{
		SessionId: id, Name: file.GetName(), Sha256: file.GetSha256(), ChunkBytes: 3 << 20})
	if err != nil {
		return err
	}
	hash := sha256.New()
	var received int64
	for {
		chunk, err := stream.Recv()
		if err == io.EOF {
			break
		}
		if err != nil {
			return err
		}
		if chunk.GetOffset() != received {
			return fmt.Errorf("%s: a chunk at offset %d, expected %d", file.GetName(), chunk.GetOffset(), received)
		}
		if _, err := part.Write(chunk.GetData()); err != nil {
			return err
		}
		hash.Write(chunk.GetData())
		received += int64(len(chunk.GetData()))
	}
	if sum := hex.EncodeToString(hash.Sum(nil)); received != file.GetBytes() || sum != file.GetSha256() {
		return fmt.Errorf("%s: %d bytes with SHA-256 %s, the daemon named %d bytes and %s",
			file.GetName(), received, sum, file.GetBytes(), file.GetSha256())
	}
	if err := part.Close(); err != nil {
		return err
	}
	if err := os.Rename(part.Name(), target); err != nil {
		return err
	}
	fmt.Fprintf(os.Stderr, "downloaded %s %d %s\n", file.GetName(), file.GetBytes(), file.GetSha256())
	return nil
}

// downloadOutputs copies every recorded file (not the checkpoints) of session id into dir.
func downloadOutputs(client lbsolidv1.SimulationClient, id, dir string, timeout time.Duration) int {
	ctx, cancel := context.WithTimeout(context.Background(), timeout)
	listed, err := client.ListOutputs(ctx, &lbsolidv1.ListOutputsRequest{SessionId: id})
	cancel()
	if err != nil {
		return rpcFailure("ListOutputs", err)
	}
	for _, file := range listed.GetFiles() {
		if strings.HasPrefix(file.GetName(), "checkpoints/") {
			continue
		}
		if err := download(client, id, file, dir, time.Hour); err != nil {
			return rpcFailure("DownloadOutput", err)
		}
	}
	return exitDone
}
