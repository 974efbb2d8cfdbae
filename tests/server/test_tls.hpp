// A TLS certificate authority and a certificate it signed for localhost and 127.0.0.1, for the
// https callback tests only (tests/server/callbacks_test.cpp): made with openssl (P-256, valid
// until 2126), the CA's own key thrown away. Nothing outside the tests trusts this CA.
#pragma once

namespace brisance::testing {

constexpr const char* kTestCa = R"PEM(-----BEGIN CERTIFICATE-----
MIIBjTCCATOgAwIBAgIUQSquzecvWB/zE1+eVt67nEkWqc8wCgYIKoZIzj0EAwIw
GzEZMBcGA1UEAwwQQnJpc2FuY2UgdGVzdCBDQTAgFw0yNjExMjcwMzA5NTVaGA8y
MTI2MTEwMzAzMDk1NVowGzEZMBcGA1UEAwwQQnJpc2FuY2UgdGVzdCBDQTBZMBMG
ByqGSM49AgEGCCqGSM49AwEHA0IABBOXRPV5VAQjO9+v3nG+exFXkQhpAwqPmfD+
bFwTSyjC6OXCfCTbdtcCbxdT/b6SKj0knHnq5xfEXrM/zXc4UBKjUzBRMB0GA1Ud
DgQWBBQ13W2ajxwobQQ6WJM5NrxxFhI7pjAfBgNVHSMEGDAWgBQ13W2ajxwobQQ6
WJM5NrxxFhI7pjAPBgNVHRMBAf8EBTADAQH/MAoGCCqGSM49BAMCA0gAMEUCIQDc
dBsSfdbSZbFBUKT0sRS4gSgI1ItN9doT5RBb5WZF0gIgT4xSpFuYCQWUJR7yzKXj
y2E55OZZdPS60Mhf67B6TpM=
-----END CERTIFICATE-----
)PEM";
constexpr const char* kLocalhostCertificate = R"PEM(-----BEGIN CERTIFICATE-----
MIIBwDCCAWagAwIBAgIUZV0XvyDum7NxcxlXLmAL/KzFfTwwCgYIKoZIzj0EAwIw
GzEZMBcGA1UEAwwQQnJpc2FuY2UgdGVzdCBDQTAgFw0yNjExMjcwMzA5NTVaGA8y
MTI2MTEwMzAzMDk1NVowFDESMBAGA1UEAwwJbG9jYWxob3N0MFkwEwYHKoZIzj0C
AQYIKoZIzj0DAQcDQgAEivoCecar0zyGhrXQ/fD9dPTp7CR0Xobr7c1Bfc/ktyrC
xrmN82oLdrXF52z2nTY4tlAMQEQnO573s23CrFkS7aOBjDCBiTAaBgNVHREEEzAR
gglsb2NhbGhvc3SHBH8AAAEwCQYDVR0TBAIwADALBgNVHQ8EBAMCB4AwEwYDVR0l
BAwwCgYIKwYBBQUHAwEwHQYDVR0OBBYEFMtAfeHu/4aSAfAWxM4WiBOH/mM5MB8G
A1UdIwQYMBaAFDXdbZqPHChtBDpYkzk2vHEWEjumMAoGCCqGSM49BAMCA0gAMEUC
IQCeLvuRCo7xqfNZCKd7qsdcePkjQns1tG9b/wFKpVALEAIgcl7nNVYQ6c1cCMLg
gMVHg7aBDTSmpAjjB8WzWAsBzhk=
-----END CERTIFICATE-----
)PEM";
constexpr const char* kLocalhostKey = R"PEM(-----BEGIN PRIVATE KEY-----
MIGHAgEAMBMGByqGSM49AgEGCCqGSM49AwEHBG0wawIBAQQgQRapNZ4VN3UGjB8E
wdnpHDk9BFw8JXnTN4umAfVbQy6hRANCAASK+gJ5xqvTPIaGtdD98P109OnsJHRe
huvtzUF9z+S3KsLGuY3zagt2tcXnbPadNji2UAxARCc7nvezbcKsWRLt
-----END PRIVATE KEY-----
)PEM";

}  // namespace brisance::testing
