#pragma once
// Messages for the user: load warnings from vaw::Assembly::warnings, load errors, plugin problems.
// Newest last; the oldest are dropped beyond a limit.
#include <QAbstractTableModel>
#include <QDateTime>
#include <QString>
#include <deque>

#include "vaw/error.hpp"

namespace vaw::ui {

class MessageLogModel : public QAbstractTableModel {
  Q_OBJECT
 public:
  enum class Severity { Info, Warning, Error };
  enum Column { SeverityColumn, MessageColumn, ColumnCount };
  static constexpr int kMaxMessages = 1000;

  explicit MessageLogModel(QObject* parent = nullptr);

  void add(Severity severity, const QString& text, const QString& detail = {});
  void add(const vaw::Diagnostic& diagnostic);
  void clear();
  [[nodiscard]] int count(Severity severity) const;
  [[nodiscard]] QString text(int row) const;

  [[nodiscard]] int rowCount(const QModelIndex& parent = {}) const override;
  [[nodiscard]] int columnCount(const QModelIndex& parent = {}) const override;
  [[nodiscard]] QVariant data(const QModelIndex& index, int role = Qt::DisplayRole) const override;
  [[nodiscard]] QVariant headerData(int section, Qt::Orientation orientation,
                                    int role = Qt::DisplayRole) const override;

 signals:
  void messageAdded(vaw::ui::MessageLogModel::Severity severity, const QString& text);

 private:
  struct Message {
    Severity severity = Severity::Info;
    QString text;
    QString detail;
    QDateTime time;
  };
  std::deque<Message> messages_;
};

}  // namespace vaw::ui
