package main

// How the client reaches a daemon on a network: TLS trusting --tls-ca, mutual TLS with
// --tls-cert/--tls-key, and a bearer token (--token-file, else $LBSOLID_TOKEN) sent as
// "authorization: Bearer <token>" on every call, also over plaintext loopback (the daemon takes
// plaintext only on loopback or a Unix socket).

import (
	"context"
	"crypto/tls"
	"crypto/x509"
	"errors"
	"fmt"
	"os"
	"strings"

	"google.golang.org/grpc"
	"google.golang.org/grpc/credentials"
)

type bearerToken string

func (t bearerToken) GetRequestMetadata(context.Context, ...string) (map[string]string, error) {
	return map[string]string{"authorization": "Bearer " + string(t)}, nil
}

func (bearerToken) RequireTransportSecurity() bool { return false }

// dialOptions are the transport and call credentials the flags ask for.
func dialOptions(o options) ([]grpc.DialOption, error) {
	var dial []grpc.DialOption
	if (o.tlsCert == "") != (o.tlsKey == "") {
		return nil, errors.New("--tls-cert, --tls-key: give both or neither")
	}
	if o.tlsCA == "" {
		if o.tlsCert != "" {
			return nil, errors.New("--tls-cert: needs --tls-ca (a client certificate is sent over TLS)")
		}
		dial = append(dial, grpc.WithInsecure())
	} else {
		pem, err := os.ReadFile(o.tlsCA)
		if err != nil {
			return nil, fmt.Errorf("--tls-ca: %v", err)
		}
		roots := x509.NewCertPool()
		if !roots.AppendCertsFromPEM(pem) {
			return nil, fmt.Errorf("--tls-ca: %s holds no PEM certificate", o.tlsCA)
		}
		config := &tls.Config{RootCAs: roots, MinVersion: tls.VersionTLS12}
		if o.tlsCert != "" {
			pair, err := tls.LoadX509KeyPair(o.tlsCert, o.tlsKey)
			if err != nil {
				return nil, fmt.Errorf("--tls-cert, --tls-key: %v", err)
			}
			config.Certificates = []tls.Certificate{pair}
		}
		dial = append(dial, grpc.WithTransportCredentials(credentials.NewTLS(config)))
	}
	token := os.Getenv("LBSOLID_TOKEN")
	if o.tokenFile != "" {
		text, err := os.ReadFile(o.tokenFile)
		if err != nil {
			return nil, fmt.Errorf("--token-file: %v", err)
		}
		token = strings.SplitN(string(text), "\n", 2)[0]
		if strings.TrimSpace(token) == "" {
			return nil, fmt.Errorf("--token-file: %s is empty", o.tokenFile)
		}
	}
	if token = strings.TrimSpace(token); token != "" {
		dial = append(dial, grpc.WithPerRPCCredentials(bearerToken(token)))
	}
	return dial, nil
}
